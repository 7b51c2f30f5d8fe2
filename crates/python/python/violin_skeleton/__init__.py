"""violin_skeleton: turn a solo violin recording into a violinist skeleton animation.

The Rust pipeline behind the ``violin-skeleton`` command-line tool, with NumPy in and out::

    import violin_skeleton as vs

    analysis = vs.analyze("take1.wav")          # or vs.analyze(samples, sr=44100)
    print(analysis.tempo_bpm, analysis.beats_s[:4], len(analysis.notes))
    analysis.save("take1_analysis.json")        # the CLI's analysis.json

    motion = vs.generate("take1.wav")           # method="rules" (default) or "gru"
    motion.joints.shape                         # (frames, 10, 2) pixels at motion.fps
    motion.save("take1.bvh")                    # json, openpose, csv, npy, bvh, glb

    mel = vs.features("take1.wav", kind="mel30")  # float32 (frames, 128)

Audio arrays are float32 or float64 samples: 1-D mono, or 2-D with channels on the shorter
axis (``(channels, samples)`` as librosa returns, or ``(samples, channels)`` as soundfile
does), mixed down to mono; ``sr`` (Hz) is required for arrays and refused for paths.

The module-level functions share one lazily created :class:`Pipeline` per method, which
loads the networks once; create your own :class:`Pipeline` for other settings. Calls release
the GIL while they work. Every error is a :class:`ViolinSkeletonError` whose message names the
file; :class:`InputNotFoundError` is also a ``FileNotFoundError``, :class:`InvalidInputError` a
``ValueError`` and :class:`InputTypeError` a ``TypeError``.
"""

from __future__ import annotations

import os
import threading
from typing import Dict, Optional

# candle would run each element-wise op across every core behind a spinning barrier; the
# pipeline already runs its stages on the cores at once, so those ops stay on the calling
# thread (as in the CLI) unless the user has chosen otherwise. Set before any network runs.
os.environ.setdefault("CANDLE_NUM_THREADS", "1")

from ._native import (  # noqa: E402
    MAX_CHANNELS,
    Analysis,
    InputIsDirectoryError,
    InputNotFoundError,
    InputTypeError,
    InvalidInputError,
    Motion,
    Pipeline,
    ViolinSkeletonError,
    __version__,
    features,
)

__all__ = [
    "MAX_CHANNELS",
    "Analysis",
    "InputIsDirectoryError",
    "InputNotFoundError",
    "InputTypeError",
    "InvalidInputError",
    "Motion",
    "Pipeline",
    "ViolinSkeletonError",
    "__version__",
    "analyze",
    "default_pipeline",
    "features",
    "generate",
]

_pipelines: Dict[str, Pipeline] = {}
_lock = threading.Lock()


def default_pipeline(method: str = "rules") -> Pipeline:
    """The shared :class:`Pipeline` of the module-level functions for ``method``
    (created on first use; its networks are loaded once and kept)."""
    with _lock:
        pipeline = _pipelines.get(method)
        if pipeline is None:
            pipeline = Pipeline(method=method)
            _pipelines[method] = pipeline
        return pipeline


def analyze(path_or_array, sr: Optional[int] = None) -> Analysis:
    """Analyse a recording (or MIDI file): f0, notes with fingering, bow changes, beats,
    downbeats, tempo and arousal. ``sr`` is the sample rate in Hz of an array."""
    return default_pipeline("rules").analyze(path_or_array, sr)


def generate(path_or_array, sr: Optional[int] = None, method: str = "rules") -> Motion:
    """Violinist motion (30 fps) for a recording or MIDI file. ``method`` is ``"rules"``
    (analysis, then rule-based synthesis; default) or ``"gru"`` (the learned baseline)."""
    return default_pipeline(method).generate(path_or_array, sr)
