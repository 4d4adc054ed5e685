# Bakes through Python against `ndfmip bake`: the same files, byte for byte, and the same
# numbers in memory; the cache key's skip; inspect against `ndfmip inspect`.
import json
import os
import subprocess

import numpy as np
import pytest

import ndfmip
from conftest import BUNDLED_MAP, assert_same_folders, run_cli

METHODS = [("toksvig", {}, []), ("naive", {}, []), ("lean", {}, []),
           ("sh", {"order": 3}, ["--order", "3"]), ("vmf", {"lobes": 2, "coherent": 0.03}, ["--lobes", "2"]),
           ("ggx-fit", {"base_roughness": 0.1}, ["--base-roughness", "0.1"]),
           ("ggx-aniso", {"base_roughness": 0.1}, ["--base-roughness", "0.1"])]


@pytest.mark.parametrize("method,options,flags", METHODS, ids=[m[0] for m in METHODS])
def test_bake_to_writes_the_cli_files(cli, tmp_path, method, options, flags):
    source = str(BUNDLED_MAP)
    run_cli(cli, "bake", source, "--method", method, *flags, "-o", tmp_path / "cli.bake", "-q")
    result = ndfmip.bake_to(source, tmp_path / "py.bake", method, **options)
    assert result["status"] == "baked"
    # The manifests name the same source, options and version: every file is identical.
    assert_same_folders(tmp_path / "cli.bake", tmp_path / "py.bake")


def test_bake_to_exports_and_decode_options_match_the_cli(cli, tmp_path):
    source = str(BUNDLED_MAP)
    run_cli(cli, "bake", source, "--green-down", "--clamp", "--half", "--base-roughness", "0.2",
            "--export", "exr,png16,ktx2,dds", "-o", tmp_path / "cli.bake", "-q")
    ndfmip.bake_to(source, tmp_path / "py.bake", green_down=True, clamp=True, half=True, base_roughness=0.2,
                   exports=["exr", "png16", "ktx2", "dds"])
    assert_same_folders(tmp_path / "cli.bake", tmp_path / "py.bake")


@pytest.mark.parametrize("method,options,flags", METHODS, ids=[m[0] for m in METHODS])
def test_bake_in_memory_equals_the_cli_planes(cli, tmp_path, method, options, flags):
    run_cli(cli, "bake", BUNDLED_MAP, "--method", method, *flags, "-o", tmp_path / "cli.bake", "-q")
    baked = ndfmip.bake(BUNDLED_MAP, method, **options)
    manifest = json.loads((tmp_path / "cli.bake" / "manifest.json").read_text())
    assert baked.method == manifest["method"]
    assert baked.parameters == pytest.approx(manifest["parameters"])
    assert len(baked) == len(manifest["levels"])
    for level in manifest["levels"]:
        planes = baked.level(level["level"])
        for name, file in level["files"].items():
            on_disk = ndfmip.load_image(tmp_path / "cli.bake" / file)
            assert np.array_equal(planes[name], on_disk), (name, level["level"])


def test_bake_of_decoded_array_equals_bake_of_file_and_writes_the_same_planes(cli, tmp_path):
    normals = ndfmip.decode(BUNDLED_MAP)
    from_array = ndfmip.bake(normals, "sh", order=2)
    from_file = ndfmip.bake(BUNDLED_MAP, "sh", order=2)
    for a, b in zip(from_array.levels, from_file.levels):
        assert a.keys() == b.keys()
        assert all(np.array_equal(a[k], b[k]) for k in a)
    from_array.write(tmp_path / "py.bake")
    run_cli(cli, "bake", BUNDLED_MAP, "--method", "sh", "--order", "2", "-o", tmp_path / "cli.bake", "-q")
    planes = sorted(p.name for p in (tmp_path / "cli.bake").glob("*.exr"))
    assert planes == sorted(p.name for p in (tmp_path / "py.bake").glob("*.exr"))
    for name in planes:
        assert (tmp_path / "cli.bake" / name).read_bytes() == (tmp_path / "py.bake" / name).read_bytes()
    # The manifest of an array names no file, and the bake reads back.
    back = ndfmip.read_bake(tmp_path / "py.bake")
    assert back.source["path"] == "" and back.source["width"] == 256
    assert all(np.array_equal(back.level(3)[k], from_array.level(3)[k]) for k in back.level(3))


def test_cache_key_skips_an_up_to_date_bake(cli, tmp_path):
    out = tmp_path / "t.bake"
    first = ndfmip.bake_to(BUNDLED_MAP, out)
    assert first["status"] == "baked"
    assert ndfmip.bake_to(BUNDLED_MAP, out)["status"] == "skipped"
    assert ndfmip.bake_to(BUNDLED_MAP, out, force=True)["status"] == "baked"
    assert ndfmip.bake_to(BUNDLED_MAP, out, half=True)["status"] == "baked"  # other options: another key
    # The tool sees the same key: the Python bake is up to date for it.
    printed = run_cli(cli, "bake", BUNDLED_MAP, "--half", "-o", out)
    assert "up to date" in printed


def test_inspect_matches_the_cli(cli, tmp_path):
    out = tmp_path / "v.bake"
    ndfmip.bake_to(BUNDLED_MAP, out, "vmf", lobes=2)
    printed = json.loads(run_cli(cli, "inspect", out, "--level", "3", "--texel", "5,7", "--exponent", "64"))
    assert ndfmip.inspect(out, 3, 5, 7, exponent=64) == printed


def test_bake_options_reach_the_library():
    normals = np.ascontiguousarray(ndfmip.decode(BUNDLED_MAP)[:64, :64])
    rough = np.full((64, 64), 0.3, np.float32)
    with_map = ndfmip.bake(normals, "toksvig", roughness=rough)
    with_base = ndfmip.bake(normals, "toksvig", base_roughness=0.3)
    # A constant roughness map is the base roughness (the variances add the same way).
    assert np.allclose(with_map.level(2)["roughness_ggx"], with_base.level(2)["roughness_ggx"], atol=1e-6)
    albedo = np.full((64, 64, 3), 0.5, np.float32)
    coloured = ndfmip.bake(normals, "vmf", lobes=2, albedo=albedo, max_iterations=5, tolerance=1e-3)
    assert [p["name"] for p in coloured.planes] == ["lobe0", "lobe1", "color0", "color1"]
    assert coloured.parameters["lobes"] == 2 and coloured.parameters["em_max_iterations"] == 5
    # Each colour plane holds alpha times the colour: with a grey albedo, half the lobe's weight.
    level = coloured.level(2)
    weights = level["lobe0"][..., 0:1] + level["lobe1"][..., 0:1]
    assert np.allclose(level["color0"] + level["color1"], 0.5 * weights, atol=1e-5)


def test_normals_from_array_decodes_as_the_file_does():
    raw = ndfmip.load_image(BUNDLED_MAP)
    assert raw.dtype == np.float32 and raw.max() <= 1.0
    for options in ({}, {"green_down": True}, {"two_channel": True}, {"height": 2.0, "clamp": True}):
        assert np.array_equal(ndfmip.normals_from_array(raw, **options), ndfmip.decode(BUNDLED_MAP, **options)), options


def test_limits_refuse_large_maps_until_raised():
    ndfmip.set_limits(max_pixels=128 * 128)
    try:
        with pytest.raises(ndfmip.Error, match="pyramidwall_256.png"):
            ndfmip.decode(BUNDLED_MAP)
    finally:
        ndfmip.set_limits(max_pixels=1 << 28)
    assert ndfmip.decode(BUNDLED_MAP).shape == (256, 256, 3)


def test_engine_without_the_materials_roughness_warns(tmp_path):
    with pytest.warns(UserWarning, match="base_roughness or roughness_map"):
        ndfmip.bake_to(BUNDLED_MAP, tmp_path / "mirror.bake", engine="three", exports="ktx2")
    assert (tmp_path / "mirror.bake" / "ktx2" / "three_occlusion_roughness_metallic.ktx2").is_file()
    # As the tool: the planes only when asked for.
    assert not (tmp_path / "mirror.bake" / "ktx2" / "mean.ktx2").exists()
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ndfmip.bake_to(BUNDLED_MAP, tmp_path / "rough.bake", engine="three", exports="ktx2", base_roughness=0.3)


def test_bake_many_writes_what_the_cli_batch_writes(cli, tmp_path):
    maps = tmp_path / "maps"
    maps.mkdir()
    for name in ("a.png", "b.png"):
        (maps / name).write_bytes(BUNDLED_MAP.read_bytes())
    (maps / "c.png").write_bytes(b"not a png")
    # The tool bakes the two good maps and exits 1 for the bad one.
    done = subprocess.run([str(cli), "bake", str(maps), "--jobs", "2", "-o", str(tmp_path / "cli" / "{stem}.bake"),
                           "-q"], capture_output=True, text=True)
    assert done.returncode == 1, done.stderr
    results = ndfmip.bake_many(maps, str(tmp_path / "py" / "{stem}.bake"), jobs=2)
    assert [(os.path.basename(r["input"]), r["status"]) for r in results] == [
        ("a.png", "baked"), ("b.png", "baked"), ("c.png", "failed")]
    assert results[2]["error"].startswith(str(maps / "c.png"))
    for stem in ("a", "b"):
        assert_same_folders(tmp_path / "cli" / f"{stem}.bake", tmp_path / "py" / f"{stem}.bake")
    # Up to date now; the shards split the maps between them and cover them all.
    assert {r["status"] for r in ndfmip.bake_many(maps / "[ab].png", str(tmp_path / "py" / "{stem}.bake"))} == {
        "skipped"}
    halves = [ndfmip.bake_many(maps, str(tmp_path / "s" / "{stem}.bake"), shard=i, shards=2) for i in (0, 1)]
    assert sorted(r["input"] for half in halves for r in half) == sorted(str(maps / n) for n in ("a.png", "b.png", "c.png"))
    with pytest.raises(ndfmip.Error, match="needs {stem} or {name}"):
        ndfmip.bake_many(maps, str(tmp_path / "one.bake"))
