# envmap_to against `ndfmip envmap`: the same folder, byte for byte; its options checked.
import struct

import pytest

import ndfmip
from conftest import assert_same_folders, run_cli


def write_hdr(path, width=32, height=16):
    """A Radiance .hdr of flat (not run-length) RGBE scanlines: a sky brighter at the top, a warm
    patch, so every step (SH, GGX levels) has something to do."""
    rows = []
    for y in range(height):
        row = bytearray()
        for x in range(width):
            r, g, b = 0.2 + (height - y) / height, 0.3, 0.5 + x / width
            if 4 <= x < 8 and 3 <= y < 6:
                r, g, b = 8.0, 6.0, 2.0
            peak = max(r, g, b)
            exponent = 0
            while peak >= 1.0:
                peak /= 2.0
                exponent += 1
            scale = 256.0 / (2.0 ** exponent)
            row += struct.pack("BBBB", int(r * scale), int(g * scale), int(b * scale), 128 + exponent)
        rows.append(bytes(row))
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n".encode()
    path.write_bytes(header + b"".join(rows))


def test_envmap_to_writes_the_cli_folder(cli, tmp_path):
    source = tmp_path / "sky.hdr"
    write_hdr(source)
    options = ["--size", "16", "--levels", "2", "--samples", "16", "--dfg-size", "8", "--dfg-samples", "16",
               "--sh-order", "3", "--layout", "both", "--rotation", "30", "--ktx2"]
    run_cli(cli, "envmap", source, *options, "-o", tmp_path / "cli.env", "-q")
    report = ndfmip.envmap_to(source, tmp_path / "py.env", size=16, levels=2, samples=16, dfg_size=8,
                              dfg_samples=16, sh_order=3, layout="both", rotation=30.0, ktx2=True)
    assert_same_folders(tmp_path / "cli.env", tmp_path / "py.env")
    assert (report["width"], report["height"]) == (32, 16)
    assert len(report["perceptual_roughness"]) == 2 and report["perceptual_roughness"][0] == 0.0


def test_envmap_to_refuses_bad_options_before_reading(tmp_path):
    source = tmp_path / "sky.hdr"
    write_hdr(source)
    for options, message in [({"size": 100}, "--size 100"), ({"layout": "strip"}, "--layout 'strip'"),
                             ({"lod_mapping": "cubic"}, "--lod-mapping"), ({"dfg_size": 4}, "--dfg-size 4"),
                             ({"size": 16, "levels": 3}, "--levels 3")]:
        with pytest.raises(ndfmip.Error, match=message):
            ndfmip.envmap_to(source, tmp_path / "out.env", **options)
    assert not (tmp_path / "out.env").exists()
    with pytest.raises(ndfmip.Error, match="missing.hdr"):
        ndfmip.envmap_to(tmp_path / "missing.hdr", tmp_path / "out.env")
