"""ndfmip: normal-map filtering (Toksvig; Han et al. 2007) from Python.

The functions mirror the command-line tool and call the same library, so their results are
the tool's, bit for bit: ``bake_to`` writes the folder ``ndfmip bake`` writes, ``render`` draws
the image ``ndfmip render`` draws. Images are numpy float32 arrays shaped (H, W, C), rows top
first. Arrays ndfmip returns own the library's buffer (no copy); float32 C-contiguous arrays
are read in place, and arrays ndfmip returned go back in without any copy. The GIL is released
while the library works, so threads run in parallel. Every failure raises ``ndfmip.Error`` (a
``ValueError``) with the tool's one-line message, naming the file or option.
"""
from __future__ import annotations

import os
import warnings
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

import numpy as np

from . import _ndfmip
from ._ndfmip import Error

__version__: str = _ndfmip.__version__

PathLike = Union[str, "os.PathLike[str]"]

__all__ = [
    "Bake", "Error", "bake", "bake_many", "bake_to", "compare", "decode", "envmap_to", "evaluate", "inspect", "load_image",
    "method_parameters", "normals_from_array", "read_bake", "render", "set_limits", "__version__",
]


def decode(path: PathLike, green_down: bool = False, two_channel: bool = False, signed: bool = False,
           height: Optional[float] = None, clamp: bool = False) -> np.ndarray:
    """A normal map file as unit tangent-space normals, (H, W, 3) float32 (OpenGL convention).

    green_down: DirectX-style map (flip Y); two_channel: rebuild z from R, G (BC5-style);
    signed: float (EXR) maps already in [-1, 1]; height: the file is a height map, SCALE the
    height of value 1.0 in texels; clamp: the map does not tile.
    """
    return _ndfmip.decode(os.fspath(path), green_down, two_channel, signed, height, clamp)


def normals_from_array(array: np.ndarray, green_down: bool = False, two_channel: bool = False,
                       signed: bool = False, height: Optional[float] = None,
                       clamp: bool = False) -> np.ndarray:
    """Raw texel values (float32 (H, W, C), as load_image returns them: [0, 1], or [-1, 1] with
    signed) decoded into unit normals as decode() does a file."""
    return _ndfmip.normals_from_array(array, green_down, two_channel, signed, height, clamp)


def load_image(path: PathLike) -> np.ndarray:
    """Any image file ndfmip reads (PNG, JPEG, TGA, BMP, OpenEXR, HDR) as float32 (H, W, C):
    integer formats scaled to [0, 1], float formats as stored."""
    return _ndfmip.load_image(os.fspath(path))


class Bake:
    """A bake in memory: per level, one parameter image ("plane") per name.

    method: the method's name; planes: name, channels, description, linear per plane;
    parameters: the bake's numbers (order, lobes, EM statistics ...); levels: per level a dict
    plane name -> read-only float32 array (H, W, C) over the bake's own buffer.
    """

    def __init__(self, native: "_ndfmip.Bake") -> None:
        self._native = native

    @property
    def method(self) -> str:
        return self._native.method

    @property
    def parameters(self) -> Dict[str, float]:
        return self._native.parameters

    @property
    def planes(self) -> List[Dict[str, Any]]:
        return self._native.planes

    @property
    def source(self) -> Dict[str, Any]:
        """Where it came from: path ('' for an array), sha256, width, height."""
        return self._native.source

    def __len__(self) -> int:
        return self._native.level_count

    def level(self, level: int) -> Dict[str, np.ndarray]:
        """The planes of one level (0 = the map's size)."""
        return self._native.level(level)

    @property
    def levels(self) -> List[Dict[str, np.ndarray]]:
        return [self._native.level(k) for k in range(self._native.level_count)]

    def write(self, dir: PathLike, exports: Union[None, str, Sequence[str]] = None, half: bool = False,
              export_textures: str = "normal,roughness", normal_format: str = "bc5",
              roughness_format: str = "bc4", zstd: int = 0, engine: str = "") -> None:
        """Writes the bake folder as ``ndfmip bake -o DIR`` does (manifest.json and the files
        ``exports`` lists: exr (the default), png16, ktx2, dds, holding what ``export_textures``
        lists: normal, roughness, planes); atomic, as the tool's."""
        self._native.write(os.fspath(dir), exports, half, export_textures, normal_format,
                           roughness_format, zstd, engine)

    def __repr__(self) -> str:
        s = self.source
        return f"<ndfmip.Bake {self.method} {s['width']}x{s['height']}, {len(self)} levels>"


def method_parameters() -> List[Dict[str, Any]]:
    """Every method's own parameters, as the methods declare them: method, key (the keyword
    bake(), bake_to() and render() take), flag (the command line's), type, min, max, default,
    help and the commands that take it."""
    return _ndfmip.method_parameters()


def bake(normals: Union[PathLike, np.ndarray], method: str = "toksvig", *, base_roughness: float = 0.0,
         roughness: Optional[np.ndarray] = None, albedo: Optional[np.ndarray] = None,
         green_down: bool = False, two_channel: bool = False, signed: bool = False,
         height: Optional[float] = None, clamp: bool = False, **parameters: float) -> Bake:
    """Bakes a normal map in memory with ``method`` (naive, toksvig, sh, vmf, lean).

    normals: a file (decoded with green_down ... clamp, as decode()) or unit normals
    (float32 (H, W, 3), e.g. from decode()). base_roughness: the material's alpha; roughness:
    toksvig, the material's alpha per texel (float32 (H, W)); albedo: vmf, linear RGB per texel
    (float32 (H, W, 3)). parameters: the method's own, by key (method_parameters()): order (sh's
    highest band, default 7); lobes (vmf's lobes per texel, default 4), coherent (default 0:
    plain lobes; bake_to, which writes files for hardware filtering, defaults to 0.03),
    lobe_budget, max_iterations, tolerance (as --coherent, --lobe-budget, --max-iterations,
    --tolerance).
    """
    if not isinstance(normals, (str, os.PathLike, np.ndarray)):
        raise Error(f"normals: expected a file path or a numpy array, not {type(normals).__name__}")
    native = _ndfmip.bake(normals, method, parameters, base_roughness, roughness, albedo, green_down,
                          two_channel, signed, height, clamp)
    return Bake(native)


def read_bake(dir: PathLike) -> Bake:
    """A bake folder (every level) back in memory, checked as the tool checks it."""
    return Bake(_ndfmip.read_bake(os.fspath(dir)))


def _path(p: Optional[PathLike]) -> str:
    return "" if p is None else os.fspath(p)


def _bake_file_options(method: str = "toksvig", *,
                       albedo: Optional[PathLike] = None, half: bool = False,
                       gloss: Optional[PathLike] = None, max_exponent: float = 0.0,
                       base_roughness: float = 0.0, roughness_map: Optional[PathLike] = None,
                       roughness_channel: str = "r", roughness_encoding: str = "perceptual",
                       engine: Optional[str] = None, metallic_channel: Optional[str] = None,
                       occlusion_channel: Optional[str] = None,
                       exports: Union[None, str, Sequence[str]] = None,
                       export_textures: str = "normal,roughness", normal_format: str = "bc5",
                       roughness_format: str = "bc4", zstd: int = 0, force: bool = False,
                       green_down: bool = False, two_channel: bool = False, signed: bool = False,
                       height: Optional[float] = None, clamp: bool = False, stacklevel: int = 3,
                       **parameters: float) -> Any:
    if engine and base_roughness == 0.0 and roughness_map is None:
        # As the tool warns: the engine files' level 0 roughness is the normals' spread alone.
        warnings.warn(f"engine {engine!r} without base_roughness or roughness_map: level 0 roughness is ~0 "
                      "(a mirror) where the map is flat; give the material's roughness", stacklevel=stacklevel)
    return _ndfmip.bake_file_options(method, parameters, _path(albedo), half, _path(gloss), max_exponent,
                                     base_roughness, _path(roughness_map), roughness_channel,
                                     roughness_encoding, engine or "", metallic_channel or "",
                                     occlusion_channel or "", exports, export_textures, normal_format,
                                     roughness_format, zstd, force, green_down, two_channel, signed,
                                     height, clamp)


def bake_to(input: PathLike, output: PathLike, method: str = "toksvig", *,
            albedo: Optional[PathLike] = None, half: bool = False,
            gloss: Optional[PathLike] = None, max_exponent: float = 0.0, base_roughness: float = 0.0,
            roughness_map: Optional[PathLike] = None, roughness_channel: str = "r",
            roughness_encoding: str = "perceptual", engine: Optional[str] = None,
            metallic_channel: Optional[str] = None, occlusion_channel: Optional[str] = None,
            exports: Union[None, str, Sequence[str]] = None, export_textures: str = "normal,roughness",
            normal_format: str = "bc5", roughness_format: str = "bc4", zstd: int = 0, force: bool = False,
            green_down: bool = False, two_channel: bool = False, signed: bool = False,
            height: Optional[float] = None, clamp: bool = False, **parameters: float) -> Dict[str, Any]:
    """``ndfmip bake INPUT -o OUTPUT`` for one map, with the same options (by the same names:
    --lobe-budget is lobe_budget, --export is exports; the method's own parameters as
    keywords, method_parameters()) and the same files, byte for byte.

    Skips the map when OUTPUT already holds a bake of the same source, options and version
    (the cache key in its manifest) unless force. Returns what happened: status ("baked" or
    "skipped"), cache_key, and for a bake its size, levels, parameters and seconds.
    """
    options = _bake_file_options(
        method, albedo=albedo, half=half, gloss=gloss, max_exponent=max_exponent,
        base_roughness=base_roughness, roughness_map=roughness_map, roughness_channel=roughness_channel,
        roughness_encoding=roughness_encoding, engine=engine, metallic_channel=metallic_channel,
        occlusion_channel=occlusion_channel, exports=exports, export_textures=export_textures,
        normal_format=normal_format, roughness_format=roughness_format, zstd=zstd, force=force,
        green_down=green_down, two_channel=two_channel, signed=signed, height=height, clamp=clamp,
        **parameters)
    return _ndfmip.bake_to(os.fspath(input), os.fspath(output), options)


def bake_many(inputs: Union[PathLike, Sequence[PathLike]], output: str, method: str = "toksvig", *,
              jobs: int = 1, shard: int = 0, shards: int = 1, **options: Any) -> List[Dict[str, Any]]:
    """``ndfmip bake INPUTS... -o PATTERN --jobs J --shard SHARD/SHARDS``: many maps at once.

    inputs are files, folders (their image files) or globs; output is a pattern with {stem},
    {name} or {parent} (e.g. ``"out/{stem}.bake"``); jobs maps are baked at a time, sharing the
    cores; only the maps of shard `shard` of `shards` are baked (the split the tool makes, the
    same on every machine). options are bake_to's keywords. Returns, per map of the shard, its
    input, output, status ("baked", "skipped" when up to date, "failed" with its "error") and
    seconds: one map's failure does not stop the others and raises nothing; a bad pattern,
    shard or option raises ndfmip.Error before any map is baked.
    """
    paths = [inputs] if isinstance(inputs, (str, os.PathLike)) else list(inputs)
    file_options = _bake_file_options(method, **options)
    return _ndfmip.bake_many([os.fspath(p) for p in paths], output, file_options, jobs, shard, shards)


def envmap_to(input: PathLike, output: PathLike, *, intensity: float = 1.0, rotation: float = 0.0,
              sh_order: int = 8, size: int = 0, levels: int = 0, samples: int = 1024,
              layout: str = "equirect", lod_mapping: str = "filament", dfg_size: int = 128,
              dfg_samples: int = 4096, half: bool = False, ktx2: bool = False,
              dds: bool = False) -> Dict[str, Any]:
    """``ndfmip envmap INPUT -o OUTPUT`` with the same options (--sh-order is sh_order and so on;
    size and levels 0: the tool's defaults) and the same files, byte for byte: an
    equirectangular .hdr or .exr map's SH, GGX-prefiltered levels and DFG table
    (docs/ENVIRONMENT.md). Returns the map's size, the texels with negative values set to 0,
    each GGX level's perceptual roughness and the seconds taken.
    """
    return _ndfmip.envmap_to(os.fspath(input), os.fspath(output), intensity, rotation, sh_order, size,
                             levels, samples, layout, lod_mapping, dfg_size, dfg_samples, half, ktx2, dds)


def inspect(dir: PathLike, level: int, x: int, y: int, exponent: Optional[float] = None) -> Dict[str, Any]:
    """One texel of a bake folder, as ``ndfmip inspect DIR --level L --texel X,Y`` prints it
    (x the column, y the row from the top)."""
    return _ndfmip.inspect(os.fspath(dir), level, x, y, exponent)


def render(scene: Union[PathLike, Dict[str, Any]], method: Optional[str] = None, spp: Optional[int] = None, *,
           bake: Optional[PathLike] = None, seed: int = 1, truth: str = "box", taps: int = 2,
           lod_bias: float = -0.5, lobe_filter: str = "texel", anisotropy: int = 1,
           roughness_mapping: str = "ours", base_dir: Optional[PathLike] = None,
           specular_aa: float = 0.0, specular_aa_threshold: float = 0.2,
           **parameters: float) -> np.ndarray:
    """A scene (a file, or its JSON as a dict; docs/SCENES.md) drawn as ``ndfmip render``
    draws it: RGB radiance, float32 (H, W, 3).

    method: a method, toksvig-lut, roughness-mips, exact or groundtruth (default: the
    scene's); spp: samples per pixel (default 1, ground truth 64); bake: a bake folder instead
    of baking the map; parameters: for a method baked on the fly (order: sh's, default 7;
    lobes: vmf's, default 4; method_parameters()); base_dir: where a dict's
    relative paths start (default: the working directory); specular_aa: an engine's geometric
    specular anti-aliasing for the single-lobe shaders (--specular-aa; 0 off, Filament's 0.15).
    """
    return _ndfmip.render(scene if isinstance(scene, dict) else os.fspath(scene), method, spp,
                          "" if bake is None else os.fspath(bake), seed, truth, taps, lod_bias, lobe_filter,
                          anisotropy, parameters, roughness_mapping,
                          "" if base_dir is None else os.fspath(base_dir), specular_aa,
                          specular_aa_threshold)


def compare(a: Union[PathLike, np.ndarray], b: Union[PathLike, np.ndarray],
            channel: Optional[int] = None) -> Dict[str, Optional[float]]:
    """Error statistics of image ``a`` against the reference ``b`` (arrays or files), as
    ``ndfmip compare`` prints them: width, height, channels, rmse, rel_rmse, psnr,
    energy_ratio, max_abs_error (None where not finite)."""
    return _ndfmip.compare(a, b, channel)


def evaluate(maps: Iterable[PathLike], output: Optional[PathLike] = None, *,
             methods: Optional[Sequence[str]] = None, footprints: Optional[Sequence[int]] = None,
             brdfs: Optional[Sequence[str]] = None, exponents: Optional[Sequence[float]] = None,
             roughness: Optional[Sequence[float]] = None, pixels: int = 128, spp: int = 0, frames: int = 8,
             seed: int = 1, aligned: bool = False, offset: Sequence[float] = (0.31, 0.17), truth: str = "box",
             taps: Optional[int] = None, lod_bias: Optional[float] = None, lobe_filter: Optional[str] = None,
             coherent: Optional[float] = None, view: str = "lab", elevation: float = 90.0,
             light_polar: float = 25.0, anisotropy: int = 1,
             specular_aa: float = 0.0, specular_aa_threshold: float = 0.2,
             calibrate: bool = False, all_images: bool = False,
             webgl: Optional[bool] = None, green_down: bool = False, two_channel: bool = False,
             signed: bool = False, height: Optional[float] = None, clamp: bool = False) -> Dict[str, Any]:
    """``ndfmip eval``: every method against the ground truth; returns report.json's content.

    With ``output``, report.json and report.html are written there too (webgl: the page's
    live view, by default with an output). Unset lists take the tool's defaults; view (lab,
    engine or aligned) sets taps, lod_bias, lobe_filter and coherent where they are None;
    anisotropy is the method rows' probes along a slanted footprint (--aniso); specular_aa
    an engine's geometric specular anti-aliasing for the single-lobe rows (--specular-aa).
    """
    o = _ndfmip.EvalOptions()
    o.maps = [os.fspath(m) for m in maps]
    o.output = "" if output is None else os.fspath(output)
    for name, value in (("methods", methods), ("footprints", footprints), ("brdfs", brdfs),
                        ("exponents", exponents), ("roughness", roughness)):
        if value is not None:
            setattr(o, name, list(value))
    o.pixels, o.spp, o.frames, o.seed = pixels, spp, frames, seed
    o.aligned, o.offset, o.truth, o.lobe_filter = aligned, list(offset), truth, lobe_filter
    o.taps, o.lod_bias, o.coherent, o.calibrate, o.all_images = taps, lod_bias, coherent, calibrate, all_images
    o.view, o.elevation, o.light_polar, o.anisotropy = view, elevation, light_polar, anisotropy
    o.specular_aa, o.specular_aa_threshold = specular_aa, specular_aa_threshold
    o.webgl = output is not None if webgl is None else webgl
    o.set_decode(green_down, two_channel, signed, height, clamp)
    return _ndfmip.evaluate(o)


def set_limits(max_pixels: Optional[int] = None, max_memory_gib: Optional[float] = None) -> None:
    """Raises (or lowers) the input limits for this process, as the tool's --max-pixels and
    --max-memory: the largest image read or rendered, and the memory a bake may need."""
    _ndfmip.set_limits(max_pixels, max_memory_gib)
