"""Shared fixtures: the command-line tool and a violin recording it made (the demo clip)."""

import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


def _cli() -> pathlib.Path:
    """The `violin-skeleton` binary: $VIOLIN_SKELETON_CLI, else the workspace's debug build."""
    env = os.environ.get("VIOLIN_SKELETON_CLI")
    if env:
        return pathlib.Path(env)
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("debug", "release"):
        candidate = target / profile / "violin-skeleton"
        if candidate.exists():
            return candidate
    found = shutil.which("violin-skeleton")
    if found:
        return pathlib.Path(found)
    pytest.fail("no violin-skeleton binary: build it (cargo build -p violin-skeleton-cli) "
                "or set VIOLIN_SKELETON_CLI")


@pytest.fixture(scope="session")
def cli() -> pathlib.Path:
    return _cli()


@pytest.fixture(scope="session")
def demo_wav(cli, tmp_path_factory) -> pathlib.Path:
    """The demo clip (Minuet in G, synthesized violin), written by `violin-skeleton demo`."""
    out = tmp_path_factory.mktemp("demo")
    subprocess.run([str(cli), "--quiet", "demo", "--out", str(out)], check=True)
    wav = out / "demo.wav"
    assert wav.is_file()
    return wav


def read_wav(path: pathlib.Path):
    """Float samples in [-1, 1] of a 16-bit PCM WAV, shape (samples, channels), and its rate."""
    import wave

    with wave.open(str(path), "rb") as w:
        assert w.getsampwidth() == 2
        frames = w.readframes(w.getnframes())
        rate = w.getframerate()
        channels = w.getnchannels()
    data = np.frombuffer(frames, dtype="<i2").astype(np.float32) / 32768.0
    return data.reshape(-1, channels), rate


@pytest.fixture(scope="session")
def demo_samples(demo_wav):
    """The demo clip as a mono float32 array and its sample rate."""
    data, rate = read_wav(demo_wav)
    return data[:, 0].copy(), rate
