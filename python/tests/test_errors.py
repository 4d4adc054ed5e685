# Bad input raises ndfmip.Error (a ValueError) with one line naming the file or option.
import numpy as np
import pytest

import ndfmip
from conftest import BUNDLED_MAP, ROOT


def raises(match, call, *args, **kwargs):
    with pytest.raises(ndfmip.Error, match=match) as caught:
        call(*args, **kwargs)
    message = str(caught.value)
    assert "\n" not in message and message
    assert isinstance(caught.value, ValueError)
    return message


def test_missing_and_corrupt_files(tmp_path):
    raises("nope.png: cannot read", ndfmip.decode, tmp_path / "nope.png")
    corrupt = tmp_path / "corrupt.png"
    corrupt.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\x00" * 40)
    raises("corrupt.png", ndfmip.decode, corrupt)
    raises("corrupt.png", ndfmip.bake, corrupt)
    raises("corrupt.png", ndfmip.bake_to, corrupt, tmp_path / "out.bake")
    assert not (tmp_path / "out.bake").exists()
    raises("nope.bake", ndfmip.read_bake, tmp_path / "nope.bake")
    raises("nope.bake", ndfmip.inspect, tmp_path / "nope.bake", 0, 0, 0)
    raises("nope.json", ndfmip.render, tmp_path / "nope.json")


def test_bad_options():
    raises("unknown method 'nope'", ndfmip.bake, BUNDLED_MAP, "nope")
    raises("unknown method 'nope'", ndfmip.bake_to, BUNDLED_MAP, "/tmp/never.bake", "nope")
    raises("lobes 9", ndfmip.bake, BUNDLED_MAP, "vmf", lobes=9)
    raises("--lobes 9", ndfmip.bake_to, BUNDLED_MAP, "/tmp/never.bake", "vmf", lobes=9)
    raises("order applies to method sh", ndfmip.bake, BUNDLED_MAP, "toksvig", order=3)
    raises("--export 'gif'", ndfmip.bake_to, BUNDLED_MAP, "/tmp/never.bake", exports="exr,gif")
    raises("tolerance", ndfmip.bake, BUNDLED_MAP, "vmf", tolerance=float("nan"))
    raises("unknown method", ndfmip.render, ROOT / "scenes" / "aligned_ortho.json", "nope")
    raises("spp 0", ndfmip.render, ROOT / "scenes" / "aligned_ortho.json", "toksvig", 0)
    raises("--footprints", ndfmip.evaluate, [BUNDLED_MAP], footprints=[0])
    # The method parameters are the methods' tables' keys, typed and ranged as there.
    raises("unknown keyword 'bands'", ndfmip.bake, BUNDLED_MAP, "sh", bands=3)
    raises("lobes: expected an integer", ndfmip.bake, BUNDLED_MAP, "vmf", lobes=2.5)
    raises("lobes: expected a number", ndfmip.bake, BUNDLED_MAP, "vmf", lobes=True)
    raises("max_iterations applies to method vmf only", ndfmip.bake, BUNDLED_MAP, "toksvig", max_iterations=5)
    raises("--max-iterations applies to --method vmf only", ndfmip.bake_to, BUNDLED_MAP, "/tmp/never.bake",
           "toksvig", max_iterations=5)
    raises("lobes 9", ndfmip.render, ROOT / "scenes" / "aligned_ortho.json", "vmf", lobes=9)
    raises("unknown parameter 'coherent'", ndfmip.render, ROOT / "scenes" / "aligned_ortho.json", "vmf",
           coherent=1.0)  # a bake option, not one of a render's


def test_method_parameters_are_the_tables():
    table = ndfmip.method_parameters()
    lobes = [p for p in table if p["key"] == "lobes"]
    assert len(lobes) == 1 and lobes[0]["method"] == "vmf" and lobes[0]["flag"] == "--lobes"
    assert (lobes[0]["min"], lobes[0]["max"], lobes[0]["default"], lobes[0]["type"]) == (1, 8, 4, "int")
    assert set(lobes[0]["commands"]) == {"bake", "render", "view", "eval"}
    order = [p for p in table if p["key"] == "order"]
    assert order and order[0]["method"] == "sh" and "render" in order[0]["commands"]
    assert all(p["min"] <= p["default"] <= p["max"] for p in table)


def test_bad_arrays():
    good = np.zeros((8, 8, 3), np.float32)
    good[..., 2] = 1
    nan = good.copy()
    nan[3, 5, 0] = np.nan
    raises(r"texel \(5, 3\)", ndfmip.bake, nan)
    raises("NaN", ndfmip.normals_from_array, nan, signed=True)
    raises("float32, not int64", ndfmip.bake, good.astype(np.int64))
    raises("float32, not float64", ndfmip.bake, good.astype(np.float64))
    raises(r"shape \(H, W, C\) with C = 3, not \(8, 8, 4\)", ndfmip.bake, np.zeros((8, 8, 4), np.float32))
    raises(r"not \(8\)", ndfmip.compare, np.zeros(8, np.float32), np.zeros(8, np.float32))
    raises("expected a file path or a numpy array", ndfmip.bake, [[0.0, 0.0, 1.0]])
    raises(r"not a normal of length 1 or less", ndfmip.bake, good * 2)
    raises("roughness", ndfmip.bake, good, "toksvig", roughness=np.zeros((4, 4), np.float32))
    raises("roughness", ndfmip.bake, good, "toksvig", roughness=np.full((8, 8), 2, np.float32))
    raises(r"a vs b: image sizes differ", ndfmip.compare, good, np.zeros((4, 4, 3), np.float32))
    # A strided view is read through a copy, not refused.
    wide = np.zeros((8, 16, 3), np.float32)
    wide[..., 2] = 1
    assert ndfmip.bake(wide[:, ::2]).level(0)["mean"].shape == (8, 8, 3)
