# What the module promises about memory and threads: arrays over the library's own buffers
# (no copies), the GIL released while the library works, and nothing kept after a call.
import json
import os
import threading
import time

import numpy as np

import ndfmip
from conftest import BUNDLED_MAP, ROOT


def test_returned_arrays_own_the_library_buffer():
    normals = ndfmip.decode(BUNDLED_MAP)
    assert normals.dtype == np.float32 and normals.flags["C_CONTIGUOUS"] and normals.flags["WRITEABLE"]
    assert not normals.flags["OWNDATA"] and type(normals.base).__name__ == "PyCapsule"
    baked = ndfmip.bake(normals, "toksvig")
    # toksvig's level-0 mean is the pyramid's base: the very array that went in.
    assert np.shares_memory(baked.level(0)["mean"], normals)
    assert np.shares_memory(baked.level(2)["roughness_ggx"], baked.level(2)["roughness_ggx"])
    assert not baked.level(1)["mean"].flags["WRITEABLE"]  # shared with the bake: read-only
    # Any other array is copied once into the library's storage.
    mine = np.array(normals)
    assert not np.shares_memory(ndfmip.bake(mine, "toksvig").level(0)["mean"], mine)
    # The arrays keep the bake's buffers alive on their own.
    level = ndfmip.bake(BUNDLED_MAP, "toksvig").level(3)["mean"]
    assert level.shape == (32, 32, 3) and np.isfinite(level).all()


def test_the_gil_is_released_while_baking():
    normals = np.ascontiguousarray(np.tile(ndfmip.decode(BUNDLED_MAP), (2, 2, 1)))
    result = {}
    worker = threading.Thread(target=lambda: result.setdefault("bake", ndfmip.bake(normals, "vmf", lobes=4)))
    start = time.perf_counter()
    worker.start()
    spins = 0
    while worker.is_alive():
        spins += 1  # only runs while the bake does not hold the GIL
    seconds = time.perf_counter() - start
    worker.join()
    assert result["bake"].method == "vmf"
    assert seconds > 0.05, "the bake was too quick to tell"
    # Held, the GIL would let this loop run only in the gaps of the switch interval.
    assert spins > 10000 * seconds, (spins, seconds)


def resident_bytes() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_no_growth_over_a_thousand_calls(tmp_path):
    small = np.ascontiguousarray(ndfmip.decode(BUNDLED_MAP)[:64, :64])
    scene = json.loads((ROOT / "scenes" / "aligned_ortho.json").read_text())
    scene["camera"]["width"] = scene["camera"]["height"] = 16

    def calls(count):
        for i in range(count):
            baked = ndfmip.bake(small, "toksvig" if i % 2 else "lean")
            baked.level(0)
            ndfmip.normals_from_array(small, signed=True)
            ndfmip.compare(small, small)
            try:
                ndfmip.decode(tmp_path / "missing.png")
            except ndfmip.Error:
                pass
            if i % 10 == 0:
                ndfmip.render(scene, "naive", base_dir=ROOT / "scenes")

    calls(100)  # allocator pools and caches settle
    before = resident_bytes()
    calls(1000)
    grown = resident_bytes() - before
    # A leaked 64x64 bake per call alone would be ~100 MB.
    assert grown < 16 * 2**20, f"resident memory grew by {grown / 2**20:.1f} MiB over 1000 calls"
