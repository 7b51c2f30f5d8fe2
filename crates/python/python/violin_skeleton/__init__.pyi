"""Type stubs of violin_skeleton (see the package docstring)."""

import os
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
MAX_CHANNELS: int

PathLike = Union[str, "os.PathLike[str]"]
AudioInput = Union[PathLike, npt.NDArray[np.floating[Any]]]
SampleRate = Optional[int]

class ViolinSkeletonError(Exception):
    """Base class of every error raised by violin_skeleton; the message names the file."""

class InputNotFoundError(ViolinSkeletonError, FileNotFoundError):
    """The input file does not exist."""

class InputIsDirectoryError(ViolinSkeletonError, IsADirectoryError):
    """A directory was given where an audio or MIDI file is expected."""

class InvalidInputError(ViolinSkeletonError, ValueError):
    """An argument has a wrong value: array shape, NaN samples, sample rate, format name."""

class InputTypeError(ViolinSkeletonError, TypeError):
    """An argument has a wrong type, e.g. an integer array where float samples are expected."""

class Analysis:
    """What the analysis found; times in seconds from the start of the input."""

    @property
    def duration_s(self) -> float: ...
    @property
    def sample_rate(self) -> int:
        """The input's sample rate in Hz (0 for MIDI)."""
    @property
    def source(self) -> str:
        """``"audio"`` or ``"midi"``."""
    @property
    def f0_hop_s(self) -> float: ...
    @property
    def f0_hz(self) -> npt.NDArray[np.float32]:
        """f0 per frame in Hz, 0 where unvoiced."""
    @property
    def voiced_prob(self) -> npt.NDArray[np.float32]: ...
    @property
    def beats_s(self) -> npt.NDArray[np.float64]: ...
    @property
    def downbeats_s(self) -> npt.NDArray[np.float64]: ...
    @property
    def bow_changes_s(self) -> npt.NDArray[np.float64]: ...
    @property
    def arousal(self) -> npt.NDArray[np.float32]:
        """Arousal in [-1, 1], ``arousal_rate_hz`` values per second."""
    @property
    def arousal_rate_hz(self) -> float: ...
    @property
    def tempo_bpm(self) -> float: ...
    @property
    def notes(self) -> List[Dict[str, Any]]:
        """One dict per note: onset_s, offset_s, midi and (when playable) string, position, finger."""
    def to_dict(self) -> Dict[str, Any]:
        """analysis.json as Python values."""
    def to_json(self) -> str:
        """analysis.json text."""
    def save(self, path: PathLike) -> None:
        """Write analysis.json (the CLI's bytes), atomically."""

class Motion:
    """A violinist skeleton animation."""

    @property
    def joints(self) -> npt.NDArray[np.float32]:
        """(frames, joints, 2) in image pixels."""
    @property
    def joints_3d(self) -> Optional[npt.NDArray[np.float32]]:
        """(frames, joints, 3) of the 3-D rig, or None (method="gru")."""
    @property
    def joint_names(self) -> List[str]: ...
    @property
    def fps(self) -> float: ...
    @property
    def duration_s(self) -> float: ...
    @property
    def image_size(self) -> Optional[Tuple[int, int]]: ...
    def save(self, path: PathLike, format: Optional[str] = None) -> None:
        """Write json, openpose (a folder, fitted to 1280x720 as the CLI does), csv, npy, bvh or glb; default from the extension."""
    def __len__(self) -> int: ...

class Pipeline:
    """Networks loaded once and reused; calls release the GIL."""

    def __init__(
        self,
        method: str = "rules",
        beats: str = "learned",
        bowing_net: str = "ensemble",
        time_signature: Optional[str] = None,
        tempo_bpm: Union[float, Tuple[float, float], None] = None,
    ) -> None:
        """time_signature ("3/4", "6/8") and tempo_bpm at the notated beat (a value, taken
        +-15 %, or a (slowest, fastest) pair) are what is known of an audio file's beat."""
    @property
    def method(self) -> str: ...
    def analyze(self, path_or_array: AudioInput, sr: SampleRate = None) -> Analysis: ...
    def generate(self, path_or_array: AudioInput, sr: SampleRate = None) -> Motion: ...

def default_pipeline(method: str = "rules") -> Pipeline: ...
def analyze(path_or_array: AudioInput, sr: SampleRate = None) -> Analysis: ...
def generate(
    path_or_array: AudioInput, sr: SampleRate = None, method: str = "rules"
) -> Motion: ...
def features(
    path_or_array: AudioInput, kind: str = "mel30", sr: SampleRate = None
) -> npt.NDArray[np.float32]:
    """float32 (frames, bands): mel30 = 30 fps x 128, mel2 = the emotion network's 64 bands."""
