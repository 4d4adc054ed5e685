# Hostile input through the Python module: paths that a NUL would cut short, arrays whose copy
# the limits forbid or memory cannot hold, dtypes that are float32 all the same, and bytes in
# messages that are not text. Each raises ndfmip.Error with one line, or works.
import numpy as np
import pytest

import ndfmip
from conftest import BUNDLED_MAP


def raises(match, call, *args, **kwargs):
    with pytest.raises(ndfmip.Error, match=match) as caught:
        call(*args, **kwargs)
    message = str(caught.value)
    assert "\n" not in message and message
    return message


@pytest.fixture
def limits():
    yield ndfmip.set_limits
    ndfmip.set_limits(max_pixels=1 << 28, max_memory_gib=16)


def flat(height, width):
    normals = np.zeros((height, width, 3), np.float32)
    normals[..., 2] = 1
    return normals


def test_nul_and_control_characters_in_paths_are_refused(tmp_path):
    png = tmp_path / "a.png"
    png.write_bytes(BUNDLED_MAP.read_bytes())
    # Without the check, "a.png\0x" reads a.png and "X\0/../../elsewhere" writes beside X.
    raises("NUL character", ndfmip.decode, str(png) + "\0x")
    raises("NUL character", ndfmip.load_image, str(png) + "\0x")
    raises("NUL character", ndfmip.bake, str(png) + "\0x")
    raises("NUL character", ndfmip.compare, str(png) + "\0x", str(png))
    escape = str(tmp_path / "X") + "\0/../../elsewhere"
    raises("NUL character", ndfmip.bake_to, png, escape)
    raises("control character 0x0A", ndfmip.bake_to, png, str(tmp_path / "o\nut"))
    baked = ndfmip.bake(png, "naive")
    raises("NUL character", baked.write, escape)
    raises("NUL character", ndfmip.read_bake, escape)
    raises("NUL character", ndfmip.inspect, escape, 0, 0, 0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png"]
    assert not (tmp_path.parent / "elsewhere").exists()


def test_the_limits_hold_before_an_array_is_copied(limits):
    limits(max_pixels=1)
    raises("above the limit", ndfmip.bake, flat(32, 32))
    limits(max_pixels=1 << 30, max_memory_gib=0.001)
    # 12 bytes standing for 20000 x 20000 x 3 floats (4.5 GiB): refused before any copy.
    huge = np.broadcast_to(np.float32([0, 0, 1]), (20000, 20000, 3))
    for call in (ndfmip.bake, ndfmip.normals_from_array):
        raises(r"needs 4\.5 GiB, above the limit", call, huge)
    raises(r"needs 4\.5 GiB", ndfmip.compare, huge, huge)


def test_a_copy_that_memory_cannot_hold_raises(limits):
    # Limits raised past what the process may hold: the copy itself fails and must raise, not crash.
    import resource
    limits(max_pixels=1 << 40, max_memory_gib=1e6)
    with open("/proc/self/status") as status:
        used = next(int(line.split()[1]) << 10 for line in status if line.startswith("VmSize:"))
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (used + (4 << 30), hard))
    try:
        # 16 bytes standing for 32768 x 32768 x 4 floats (16 GiB), more than the 4 GiB left.
        huge = np.broadcast_to(np.float32([0, 0, 1, 1]), (32768, 32768, 4))
        raises("cannot make a C-contiguous float32 copy", ndfmip.normals_from_array, huge)
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def test_float32_with_metadata_is_float32():
    tagged = np.dtype(np.float32, metadata={"unit": "normal"})
    normals = np.zeros((4, 4, 3), tagged)
    normals[..., 2] = 1
    assert normals.dtype == np.float32 and normals.dtype.metadata
    assert len(ndfmip.bake(normals, "naive")) == 3
    # What does differ is named: the byte order.
    message = raises("expected dtype float32 in native byte order, not >f4", ndfmip.bake,
                     flat(4, 4).astype(">f4"))
    assert "not float32" not in message


def test_threads_baking_into_one_folder_all_succeed(tmp_path):
    # Each writer stages under a name of its own (process, thread, count): threads baking beside
    # one another, some to the same output, never remove each other's staging.
    import threading
    png = tmp_path / "a.png"
    png.write_bytes(BUNDLED_MAP.read_bytes())
    outputs = [tmp_path / f"map{i}.bake" for i in range(12)] + [tmp_path / "same.bake"] * 8
    errors = []

    def bake(output):
        try:
            ndfmip.bake_to(png, output, "naive", force=True)
        except ndfmip.Error as e:
            errors.append(str(e))

    threads = [threading.Thread(target=bake, args=(o,)) for o in outputs]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    for output in set(outputs):
        assert ndfmip.read_bake(output).method == "naive"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["a.png"] + [o.name for o in set(outputs)])


def test_a_map_too_large_for_max_memory_is_refused_from_its_header(tmp_path, limits):
    # 2048 x 2048 RGB declared, data that inflates to nothing: the refusal can only come from
    # the header, before decoding, with the estimate in the message.
    import struct
    header = struct.pack(">I4sIIBBBBB", 13, b"IHDR", 2048, 2048, 8, 2, 0, 0, 0) + b"\0" * 4
    png = tmp_path / "big.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\n" + header + struct.pack(">I4s", 16384, b"IDAT") + b"\x55" * 16384)
    limits(max_memory_gib=0.01)
    message = raises("needs about", ndfmip.bake_to, png, tmp_path / "big.bake")
    assert message.startswith(str(png) + ": a toksvig bake of a 2048x2048 map needs about")
    raises("needs about", ndfmip.decode, png)
    assert not (tmp_path / "big.bake").exists()
