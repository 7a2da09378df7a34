"""Type hints of the compiled `omnishadow` module (python/src/module.cpp has the docstrings)."""

import os
from typing import Any, Sequence, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike[str]]
LightsSource = Union["Lights", PathLike, dict[str, Any], Sequence[dict[str, Any]], None]
CameraSpec = Union[str, int, dict[str, Any], None]

class InputError(ValueError):
    """Bad input: the CLI's one-line message (the CLI exits with status 2)."""

class RenderError(RuntimeError):
    """Any other failure (the CLI exits with status 1)."""

class Scene:
    @property
    def path(self) -> str: ...
    @property
    def instance_count(self) -> int: ...
    @property
    def light_names(self) -> list[str]: ...
    @property
    def camera_names(self) -> list[str]: ...
    @property
    def material_variants(self) -> list[str]: ...
    @property
    def material_variant(self) -> str | None: ...
    @property
    def warnings(self) -> list[str]: ...
    def posed(self, time: float | None, animation: str | int | None = None) -> Scene: ...

class Lights:
    @property
    def names(self) -> list[str]: ...
    @property
    def ambient(self) -> tuple[float, float, float]: ...
    @property
    def environment(self) -> dict[str, Any] | None: ...
    @property
    def ambient_occlusion(self) -> dict[str, Any] | None: ...
    @property
    def warnings(self) -> list[str]: ...

class Frame:
    @property
    def beauty(self) -> npt.NDArray[np.float32]: ...
    def to_srgb8(self, exposure: float | None = None) -> npt.NDArray[np.uint8]: ...
    @property
    def channels(self) -> list[str]: ...
    def keys(self) -> list[str]: ...
    def __getitem__(self, name: str) -> npt.NDArray[np.float32]: ...
    def __contains__(self, name: str) -> bool: ...
    @property
    def depth(self) -> npt.NDArray[np.float32]: ...
    @property
    def object_id(self) -> npt.NDArray[np.int32]: ...
    @property
    def material_id(self) -> npt.NDArray[np.int32]: ...
    @property
    def ids(self) -> dict[str, Any]: ...
    @property
    def camera(self) -> dict[str, Any]: ...
    @property
    def times(self) -> dict[str, float]: ...
    @property
    def shadow_maps(self) -> dict[str, dict[str, Any]]: ...
    @property
    def masks(self) -> dict[str, Any]: ...
    def save_masks(self, stem: PathLike) -> None: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def exposure(self) -> float: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    def save(self, path: PathLike) -> None: ...
    def save_aovs(self, path: PathLike) -> None: ...

class Renderer:
    def __init__(self, gpu: int | None = None, verbose: bool = False) -> None: ...
    @property
    def platform(self) -> str: ...
    @property
    def gl(self) -> str: ...
    def render(
        self,
        scene: Scene,
        lights: LightsSource = None,
        *,
        camera: CameraSpec = None,
        width: int | None = None,
        height: int | None = None,
        aovs: Sequence[str] | None = None,
        shading: str = "pbr",
        exposure: float = 0.0,
        aa: int = 1,
        shadow_maps: bool = False,
        masks: bool = False,
        beauty: bool = True,
        no_gltf_lights: bool = False,
        max_memory: float = 4096.0,
        shadow_pass: str = "auto",
        depth_prepass: str = "auto",
        finish_each_stage: str = "auto",
    ) -> Frame: ...
    def verify(
        self,
        scene: Scene,
        lights: LightsSource = None,
        *,
        light: str = "",
        camera: CameraSpec = None,
        width: int | None = None,
        height: int | None = None,
        shading: str = "pbr",
        grazing: float = 0.05,
        edge_texels: float = 3.0,
        source_samples: int = 64,
        max_error: float | None = None,
        no_gltf_lights: bool = False,
        max_memory: float = 4096.0,
        shadow_pass: str = "auto",
    ) -> dict[str, Any]: ...

def load_scene(
    path: PathLike,
    scene: int | None = None,
    *,
    time: float | None = None,
    animation: str | int | None = None,
    variant: str | int | None = None,
    allow_external_uris: bool = False,
) -> Scene: ...
def load_lights(
    source: Union[PathLike, dict[str, Any], Sequence[dict[str, Any]]], label: str = "lights"
) -> Lights: ...
def read_image(path: PathLike) -> tuple[npt.NDArray[np.float32], list[str]]: ...
def use_rendering_heap() -> dict[str, Any]: ...
