"""Type stubs of the compiled module (re-exported by ``trundle``)."""

import os
from typing import Any, Dict, List, Optional, Union

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
