"""Type stubs of the compiled module (re-exported by ``trundle``)."""

import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

PresetArg = Union[str, "os.PathLike[str]"]
ParamValue = Union[str, int, float]

def render(
    preset: Optional[PresetArg] = "default",
    seconds: float = 2.0,
    seed: int = 1,
    sample_rate: float = 48000,
    params: Optional[Dict[str, ParamValue]] = None,
) -> npt.NDArray[np.float32]:
    """``seconds`` of ``preset``: float32, shape (round(seconds × sample_rate), 2)."""

class Renderer:
    """A preset rendered block after block."""

    def __init__(
        self,
        preset: Optional[PresetArg] = "default",
        seed: int = 1,
        sample_rate: float = 48000,
        params: Optional[Dict[str, ParamValue]] = None,
    ) -> None: ...
    def set(self, key: str, value: ParamValue) -> None: ...
    def get(self, key: str) -> float: ...
    def render(self, frames: int) -> npt.NDArray[np.float32]: ...
    @property
    def frames_done(self) -> int: ...
    @property
    def sample_rate(self) -> float: ...
    @property
    def latency_frames(self) -> int: ...

def presets() -> List[str]:
    """The built-in presets' names."""

def parameters() -> List[Dict[str, Any]]:
    """The parameter table: key, name, unit, min, max, default, kind, choices, doc."""

Vec3 = Tuple[float, float, float]

class Contact:
    """One contact pair in one physics frame (SI units)."""

    def __init__(
        self,
        pair: int,
        body: int,
        normal_speed_m_s: float = 0.0,
        tangential_speed_m_s: float = 0.0,
        angular_speed_rad_s: float = 0.0,
        radius_m: float = 0.02,
        point_m: Sequence[float] = (0.0, 0.0, 0.0),
        normal: Sequence[float] = (0.0, 0.0, 1.0),
        normal_impulse_n_s: float = 0.0,
        materials: Sequence[int] = (0, 0),
    ) -> None: ...
    @property
    def pair(self) -> int: ...
    @property
    def body(self) -> int: ...
    @property
    def normal_speed_m_s(self) -> float: ...
    @property
    def tangential_speed_m_s(self) -> float: ...
    @property
    def angular_speed_rad_s(self) -> float: ...
    @property
    def radius_m(self) -> float: ...
    @property
    def point_m(self) -> List[float]: ...
    @property
    def normal(self) -> List[float]: ...
    @property
    def normal_impulse_n_s(self) -> float: ...
    @property
    def materials(self) -> List[int]: ...

class Material:
    """What a body is made of: the object it rings as and its surface."""

    def __init__(
        self,
        material_x: float = 0.8,
        material_y: float = 0.0,
        object_size_m: float = 1.0,
        shape: str = "plate",
        decay: float = 1.0,
        roughness: float = 0.5,
    ) -> None: ...
    @staticmethod
    def wood() -> "Material": ...
    @staticmethod
    def metal() -> "Material": ...
    @staticmethod
    def glass() -> "Material": ...

class Listener:
    """Where the stereo image is heard from."""

    def __init__(
        self,
        position_m: Sequence[float] = (0.0, -2.0, 1.0),
        right: Sequence[float] = (1.0, 0.0, 0.0),
        reference_distance_m: float = 1.0,
    ) -> None: ...

class ContactStream:
    """A physics engine's contacts in, one continuous sound per touching pair out."""

    def __init__(
        self,
        materials: Optional[Iterable[Union[Material, str]]] = None,
        sample_rate: float = 48000,
        frame_rate: float = 60,
        max_pairs: int = 64,
        max_voices: int = 8,
        seed: int = 1,
        impact_gain: float = 0.2,
        params: Optional[Dict[str, ParamValue]] = None,
        listener: Optional[Listener] = None,
        hold: Optional[Dict[str, int]] = None,
        mapping: Optional[Dict[str, float]] = None,
    ) -> None: ...
    def update(self, contacts: Iterable[Contact]) -> None: ...
    def render(self, frames: int) -> npt.NDArray[np.float32]: ...
    def events(self) -> List[Dict[str, Any]]: ...
    def remove_pair(self, pair: int) -> None: ...
    def set_listener(self, listener: Listener) -> None: ...
    @property
    def voices_started(self) -> int: ...
    @property
    def voices_sounding(self) -> int: ...
    @property
    def crowd_count(self) -> int: ...
    @property
    def dropped_events(self) -> int: ...
    @property
    def sample_rate(self) -> float: ...
    @property
    def frame_rate(self) -> float: ...

def compare(
    recording: npt.NDArray[np.float64],
    candidate: npt.NDArray[np.float64],
    recording_rate: float,
    candidate_rate: Optional[float] = None,
) -> Dict[str, Any]: ...
