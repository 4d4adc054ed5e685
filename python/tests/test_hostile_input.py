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
