# render, compare and evaluate through Python against the tool's own output.
import json

import numpy as np
import pytest

import ndfmip
from conftest import BUNDLED_MAP, ROOT, run_cli

SCENE = ROOT / "scenes" / "aligned_ortho.json"


def test_render_equals_the_cli(cli, tmp_path):
    for method, flags, options in [("toksvig", [], {}), ("vmf", ["--lobes", "2"], {"lobes": 2}),
                                   ("groundtruth", ["--spp", "4"], {"spp": 4})]:
        out = tmp_path / f"{method}.exr"
        run_cli(cli, "render", SCENE, "--method", method, *flags, "-o", out, "-q", "--no-png")
        image = ndfmip.render(SCENE, method, **options)
        assert image.shape == (64, 64, 3) and image.dtype == np.float32
        assert np.array_equal(image, ndfmip.load_image(out)), method


def test_render_of_a_scene_dict_equals_its_file():
    scene = json.loads(SCENE.read_text())
    assert np.array_equal(ndfmip.render(scene, base_dir=SCENE.parent), ndfmip.render(SCENE))


def test_render_reads_a_bake_folder(tmp_path):
    ndfmip.bake_to(BUNDLED_MAP, tmp_path / "t.bake", green_down=True)
    assert np.array_equal(ndfmip.render(SCENE, "toksvig", bake=tmp_path / "t.bake"), ndfmip.render(SCENE, "toksvig"))


def test_compare_matches_the_cli(cli, tmp_path):
    run_cli(cli, "render", SCENE, "--method", "naive", "-o", tmp_path / "a.exr", "-q", "--no-png")
    run_cli(cli, "render", SCENE, "--method", "exact", "-o", tmp_path / "b.exr", "-q", "--no-png")
    printed = json.loads(run_cli(cli, "compare", tmp_path / "a.exr", tmp_path / "b.exr"))
    from_files = ndfmip.compare(tmp_path / "a.exr", tmp_path / "b.exr")
    from_arrays = ndfmip.compare(ndfmip.render(SCENE, "naive"), ndfmip.render(SCENE, "exact"))
    for key, value in from_files.items():
        assert printed[key] == value and from_arrays[key] == value, key
    assert ndfmip.compare(tmp_path / "a.exr", tmp_path / "b.exr", channel=1)["channels"] == 1


def test_evaluate_returns_the_cli_report(cli, tmp_path):
    args = dict(methods=["toksvig", "vmf:2", "exact"], footprints=[4, 16], brdfs=["blinnphong"], exponents=[32],
                frames=2, pixels=32)
    run_cli(cli, "eval", BUNDLED_MAP, "--methods", "toksvig,vmf:2,exact", "--footprints", "4,16", "--brdfs",
            "blinnphong", "--exponents", "32", "--frames", "2", "--pixels", "32", "-o", tmp_path / "cli", "-q")
    report = ndfmip.evaluate([str(BUNDLED_MAP)], **args)
    assert report == json.loads((tmp_path / "cli" / "report.json").read_text())
    ndfmip.evaluate([str(BUNDLED_MAP)], tmp_path / "py", **args)
    assert (tmp_path / "py" / "report.json").read_bytes() == (tmp_path / "cli" / "report.json").read_bytes()
    assert (tmp_path / "py" / "report.html").stat().st_size > 0
    aligned = ndfmip.evaluate([BUNDLED_MAP], methods=["toksvig", "exact"], footprints=[4], brdfs=["ggx"],
                              roughness=[0.2], frames=0, aligned=True)
    assert aligned["setup"]["taps"] == 1 and aligned["setup"]["lod_bias"] == 0
    # The engine view, as the tool's --view engine: one lookup, parameters blended, coherent lobes.
    engine_args = dict(methods=["vmf:2"], footprints=[4], brdfs=["ggx"], roughness=[0.3], frames=0, pixels=16)
    run_cli(cli, "eval", BUNDLED_MAP, "--view", "engine", "--methods", "vmf:2", "--footprints", "4", "--brdfs", "ggx",
            "--roughness", "0.3", "--frames", "0", "--pixels", "16", "-o", tmp_path / "engine", "-q")
    engine = ndfmip.evaluate([BUNDLED_MAP], view="engine", **engine_args)
    assert engine == json.loads((tmp_path / "engine" / "report.json").read_text())
    setup = engine["setup"]
    assert (setup["eval_view"], setup["taps"], setup["lobe_filter"]) == ("engine", 1, "parameter")
    assert setup["coherent"] == pytest.approx(0.03)
    # A tilted view with anisotropic probes, as the tool's --elevation and --aniso.
    tilted_args = dict(methods=["naive"], footprints=[4], brdfs=["ggx"], roughness=[0.3], frames=0, pixels=16)
    run_cli(cli, "eval", BUNDLED_MAP, "--elevation", "30", "--aniso", "4", "--methods", "naive", "--footprints", "4",
            "--brdfs", "ggx", "--roughness", "0.3", "--frames", "0", "--pixels", "16", "-o", tmp_path / "tilted", "-q")
    tilted = ndfmip.evaluate([BUNDLED_MAP], elevation=30.0, anisotropy=4, **tilted_args)
    assert tilted == json.loads((tmp_path / "tilted" / "report.json").read_text())
    assert tilted["setup"]["anisotropy"] == 4
    # An engine's specular anti-aliasing, as the tool's --specular-aa.
    run_cli(cli, "eval", BUNDLED_MAP, "--view", "engine", "--specular-aa", "0.15", "--methods", "naive", "--footprints",
            "1", "--brdfs", "ggx", "--roughness", "0.1", "--frames", "0", "--pixels", "16", "-o", tmp_path / "aa", "-q")
    aa = ndfmip.evaluate([BUNDLED_MAP], view="engine", specular_aa=0.15, methods=["naive"], footprints=[1],
                         brdfs=["ggx"], roughness=[0.1], frames=0, pixels=16)
    assert aa == json.loads((tmp_path / "aa" / "report.json").read_text())
    assert aa["setup"]["specular_aa"]["variance"] == pytest.approx(0.15)


def test_render_with_specular_aa_equals_the_cli(cli, tmp_path):
    # The rule widens a GGX alpha (the bundled scene is Blinn-Phong's, which it leaves alone).
    scene = json.loads(SCENE.read_text())
    scene["material"] = {"brdf": "ggx", "roughness": 0.1, "albedo": 0, "specular": 1}
    scene["normal_map"]["path"] = str((SCENE.parent / scene["normal_map"]["path"]).resolve())
    path = tmp_path / "ggx.json"
    path.write_text(json.dumps(scene))
    out = tmp_path / "aa.exr"
    run_cli(cli, "render", path, "--method", "naive", "--specular-aa", "0.15", "-o", out, "-q", "--no-png")
    image = ndfmip.render(path, "naive", specular_aa=0.15)
    assert np.array_equal(image, ndfmip.load_image(out))
    assert not np.array_equal(image, ndfmip.render(path, "naive"))
