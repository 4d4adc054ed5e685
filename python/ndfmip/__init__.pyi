# Type stubs of the ndfmip package (its functions are documented in __init__.py).
import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike[str]]
FloatArray = npt.NDArray[np.float32]

__version__: str

class Error(ValueError): ...

def decode(path: PathLike, green_down: bool = ..., two_channel: bool = ..., signed: bool = ...,
           height: Optional[float] = ..., clamp: bool = ...) -> FloatArray: ...
def normals_from_array(array: FloatArray, green_down: bool = ..., two_channel: bool = ..., signed: bool = ...,
                       height: Optional[float] = ..., clamp: bool = ...) -> FloatArray: ...
def load_image(path: PathLike) -> FloatArray: ...

class Bake:
    @property
    def method(self) -> str: ...
    @property
    def parameters(self) -> Dict[str, float]: ...
    @property
    def planes(self) -> List[Dict[str, Any]]: ...
    @property
    def source(self) -> Dict[str, Any]: ...
    @property
    def levels(self) -> List[Dict[str, FloatArray]]: ...
    def __len__(self) -> int: ...
    def level(self, level: int) -> Dict[str, FloatArray]: ...
    def write(self, dir: PathLike, exports: Union[None, str, Sequence[str]] = ..., half: bool = ...,
              export_textures: str = ..., normal_format: str = ..., roughness_format: str = ..., zstd: int = ...,
              engine: str = ...) -> None: ...

def method_parameters() -> List[Dict[str, Any]]: ...
def bake(normals: Union[PathLike, FloatArray], method: str = ..., *, base_roughness: float = ...,
         roughness: Optional[FloatArray] = ..., albedo: Optional[FloatArray] = ..., green_down: bool = ...,
         two_channel: bool = ..., signed: bool = ..., height: Optional[float] = ..., clamp: bool = ...,
         **parameters: float) -> Bake: ...
def read_bake(dir: PathLike) -> Bake: ...
def bake_to(input: PathLike, output: PathLike, method: str = ..., *, albedo: Optional[PathLike] = ...,
            half: bool = ...,
            gloss: Optional[PathLike] = ..., max_exponent: float = ..., base_roughness: float = ...,
            roughness_map: Optional[PathLike] = ..., roughness_channel: str = ..., roughness_encoding: str = ...,
            engine: Optional[str] = ..., metallic_channel: Optional[str] = ...,
            occlusion_channel: Optional[str] = ..., exports: Union[None, str, Sequence[str]] = ...,
            export_textures: str = ..., normal_format: str = ..., roughness_format: str = ..., zstd: int = ...,
            force: bool = ..., green_down: bool = ..., two_channel: bool = ..., signed: bool = ...,
            height: Optional[float] = ..., clamp: bool = ..., **parameters: float) -> Dict[str, Any]: ...
def bake_many(inputs: Union[PathLike, Sequence[PathLike]], output: str, method: str = ..., *, jobs: int = ...,
              shard: int = ..., shards: int = ..., **options: Any) -> List[Dict[str, Any]]: ...
def envmap_to(input: PathLike, output: PathLike, *, intensity: float = ..., rotation: float = ...,
              sh_order: int = ..., size: int = ..., levels: int = ..., samples: int = ...,
              layout: str = ..., lod_mapping: str = ..., dfg_size: int = ..., dfg_samples: int = ...,
              half: bool = ..., ktx2: bool = ..., dds: bool = ...) -> Dict[str, Any]: ...
def inspect(dir: PathLike, level: int, x: int, y: int, exponent: Optional[float] = ...) -> Dict[str, Any]: ...
def render(scene: Union[PathLike, Dict[str, Any]], method: Optional[str] = ..., spp: Optional[int] = ..., *,
           bake: Optional[PathLike] = ..., seed: int = ..., truth: str = ..., taps: int = ...,
           lod_bias: float = ..., lobe_filter: str = ..., anisotropy: int = ...,
           roughness_mapping: str = ..., base_dir: Optional[PathLike] = ...,
           specular_aa: float = ..., specular_aa_threshold: float = ..., **parameters: float) -> FloatArray: ...
def compare(a: Union[PathLike, FloatArray], b: Union[PathLike, FloatArray],
            channel: Optional[int] = ...) -> Dict[str, Optional[float]]: ...
def evaluate(maps: Iterable[PathLike], output: Optional[PathLike] = ..., *, methods: Optional[Sequence[str]] = ...,
             footprints: Optional[Sequence[int]] = ..., brdfs: Optional[Sequence[str]] = ...,
             exponents: Optional[Sequence[float]] = ..., roughness: Optional[Sequence[float]] = ...,
             pixels: int = ..., spp: int = ..., frames: int = ..., seed: int = ..., aligned: bool = ...,
             offset: Sequence[float] = ..., truth: str = ..., taps: Optional[int] = ...,
             lod_bias: Optional[float] = ..., lobe_filter: Optional[str] = ..., coherent: Optional[float] = ..., view: str = ...,
             elevation: float = ..., light_polar: float = ..., anisotropy: int = ...,
             specular_aa: float = ..., specular_aa_threshold: float = ...,
             calibrate: bool = ..., all_images: bool = ..., webgl: Optional[bool] = ..., green_down: bool = ...,
             two_channel: bool = ..., signed: bool = ..., height: Optional[float] = ...,
             clamp: bool = ...) -> Dict[str, Any]: ...
def set_limits(max_pixels: Optional[int] = ..., max_memory_gib: Optional[float] = ...) -> None: ...
