#!/usr/bin/env python3
"""Time librosa and violin-skeleton on the same 180 s, 44.1 kHz file, in one run.

    cargo build --release -p violin-skeleton-cli
    python3 scripts/compare_librosa.py [--keep /tmp/test180.wav]

Prints, for mel 30 fps × 128 bands at 44.1 kHz (n_fft 2048, hop 1470):
  * compute only: librosa.feature.melspectrogram (best of 7, after a warm-up call) vs the
    Rust `mel` time printed by `violin-skeleton features` (best of 7 process runs);
  * whole process: `librosa.load` + mel in this interpreter vs the CLI's wall time
    (decode + mel + write .npy), best of 7.
"""
import argparse
import pathlib
import re
import subprocess
import tempfile
import time

import librosa
import numpy as np
import soundfile as sf

ROOT = pathlib.Path(__file__).resolve().parent.parent
CLI = ROOT / "target" / "release" / "violin-skeleton"


def make_audio(path, sr=44100, seconds=180):
    rng = np.random.default_rng(0)
    t = np.arange(sr * seconds) / sr
    f0 = 196 * 2 ** ((np.floor(t * 2) % 24) / 12)
    phase = 2 * np.pi * np.cumsum(f0) / sr
    y = 0.3 * np.sin(phase) + 0.1 * np.sin(2 * phase) + 0.003 * rng.standard_normal(len(t))
    sf.write(path, y.astype(np.float32), sr, subtype="PCM_16")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--keep", help="write the test file here instead of a temp dir")
    args = ap.parse_args()
    tmp = pathlib.Path(tempfile.mkdtemp())
    wav = pathlib.Path(args.keep) if args.keep else tmp / "test180.wav"
    make_audio(wav)
    kw = dict(sr=44100, n_fft=2048, hop_length=1470, n_mels=128)

    y, sr = librosa.load(wav, sr=None)
    librosa.feature.melspectrogram(y=y[:sr], **kw)  # warm-up
    lib_compute = min(
        (lambda t0: (librosa.feature.melspectrogram(y=y, **kw), time.perf_counter() - t0)[1])(
            time.perf_counter()) for _ in range(7))
    lib_total = min(
        (lambda t0: (librosa.feature.melspectrogram(y=librosa.load(wav, sr=None)[0], **kw),
                     time.perf_counter() - t0)[1])(time.perf_counter()) for _ in range(7))

    rust_compute, rust_total = [], []
    for _ in range(7):
        t0 = time.perf_counter()
        out = subprocess.run([str(CLI), "features", str(wav), "--kind", "mel30", "--scale",
                              "power", "--sample-rate", "native", "-o", str(tmp / "m.npy")],
                             capture_output=True, text=True, check=True)
        rust_total.append(time.perf_counter() - t0)
        rust_compute.append(float(re.search(r"mel ([0-9.]+) ms", out.stderr).group(1)) / 1e3)
    ours = np.load(tmp / "m.npy")
    ref = librosa.feature.melspectrogram(y=y.astype(np.float64), **kw).T
    mask = ref >= ref.max() * 1e-8
    rel = np.max(np.abs(ours[mask] - ref[mask]) / ref[mask])
    print(f"mel30 @ 44.1 kHz, 180 s ({ref.shape[0]} frames)")
    print(f"  compute only : librosa {lib_compute*1e3:7.1f} ms | violin-skeleton "
          f"{min(rust_compute)*1e3:6.1f} ms | {lib_compute/min(rust_compute):4.1f}x")
    print(f"  whole process: librosa load+mel {lib_total*1e3:7.1f} ms | violin-skeleton CLI "
          f"{min(rust_total)*1e3:6.1f} ms | {lib_total/min(rust_total):4.1f}x")
    print(f"  max relative difference (bins within 80 dB of max): {rel:.2e}")


if __name__ == "__main__":
    main()
