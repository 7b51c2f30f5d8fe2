#!/usr/bin/env python3
"""Reference fixtures for dsp-mel's parity tests, made with librosa and scipy.

Run by hand (not in CI) after `pip install librosa scipy numpy`:

    python3 scripts/make_fixtures.py

It writes small .npy and .json files under crates/dsp-mel/tests/fixtures/; the Rust tests
compare our output with them. The versions used are recorded in versions.json.
"""
import json
import pathlib

import librosa
import numpy as np
import scipy
import scipy.signal as sig

OUT = pathlib.Path(__file__).resolve().parent.parent / "crates" / "dsp-mel" / "tests" / "fixtures"
OUT.mkdir(parents=True, exist_ok=True)
rng = np.random.default_rng(20261121)


def violin_like(sr, seconds=1.5):
    """Bowed-string-like test tone: G3→A4 glide with vibrato and 20 harmonics, bow noise,
    a 0.2 s silent gap (to exercise the 80 dB floor) and a soft tail."""
    t = np.arange(int(sr * seconds)) / sr
    f0 = 196.0 * 2 ** (t / seconds * 14 / 12) * (1 + 0.006 * np.sin(2 * np.pi * 5.5 * t))
    phase = 2 * np.pi * np.cumsum(f0) / sr
    y = np.zeros_like(t)
    for h in range(1, 21):
        alias_free = (h * f0) < sr / 2
        y += alias_free * np.sin(h * phase) / h ** 1.2
    y *= 0.2
    y += 1e-3 * rng.standard_normal(len(t))
    gap = (t > 0.6) & (t < 0.8)
    y[gap] = 0.0
    y *= np.where(t > 1.2, np.exp(-(t - 1.2) * 8), 1.0)
    return y.astype(np.float32)


def mel_case(name, y, sr, **kw):
    y64 = y.astype(np.float64)
    S = librosa.feature.melspectrogram(y=y64, sr=sr, **kw)  # (n_mels, frames)
    np.save(OUT / f"{name}_power.npy", S.T.astype(np.float64))
    db = librosa.power_to_db(S, ref=1.0, amin=1e-10, top_db=80.0)
    np.save(OUT / f"{name}_db.npy", db.T.astype(np.float64))
    return S


cases = {}
for sr in (22050, 44100):
    y = violin_like(sr)
    np.save(OUT / f"signal_{sr}.npy", y)
    hop = int(round(sr / 30))
    mel_case(f"mel30_{sr}", y, sr, n_fft=2048, hop_length=hop, n_mels=128)
    cases[f"mel30_{sr}"] = dict(sr=sr, n_fft=2048, hop=hop, n_mels=128, htk=False, norm="slaney")

# HTK scale, no normalisation, fmin/fmax set, magnitude (power 1).
y = np.load(OUT / "signal_22050.npy")
mel_case("mel_htk_22050", y, 22050, n_fft=1024, hop_length=256, n_mels=40, fmin=100.0,
         fmax=8000.0, htk=True, norm=None, power=1.0)
cases["mel_htk_22050"] = dict(sr=22050, n_fft=1024, hop=256, n_mels=40, fmin=100.0, fmax=8000.0,
                              htk=True, norm=None, power=1.0)

# Emotion input: 64-band 30 fps power mel, averaged over groups of 15 frames (2 fps).
S = librosa.feature.melspectrogram(y=y.astype(np.float64), sr=22050, n_fft=2048, hop_length=735,
                                   n_mels=64)
frames = S.shape[1]
groups = [S[:, i:i + 15].mean(axis=1) for i in range(0, frames, 15)]
np.save(OUT / "mel2_22050_power.npy", np.stack(groups))

# Filters.
filters = {"butter": [], "filtfilt": [], "medfilt": [], "median_nearest": []}
for order in range(1, 9):
    for cutoff, fs in ((5.0, 30.0), (1.0, 30.0), (3000.0, 44100.0), (0.45, 1.0)):
        b, a = sig.butter(order, cutoff, fs=fs)
        sos = sig.butter(order, cutoff, fs=fs, output="sos")
        filters["butter"].append(dict(order=order, cutoff=cutoff, fs=fs, b=b.tolist(),
                                      a=a.tolist(), sos=sos.tolist()))
for order, n in ((4, 300), (2, 17), (6, 100)):
    x = np.cumsum(rng.standard_normal(n)) * 3.0 + 5.0 * np.sin(np.arange(n) * 0.4)
    b, a = sig.butter(order, 5.0, fs=30.0)
    y = sig.filtfilt(b, a, x)
    filters["filtfilt"].append(dict(order=order, b=b.tolist(), a=a.tolist(), x=x.tolist(),
                                    y=y.tolist()))
from scipy.ndimage import median_filter  # noqa: E402

for n, k in ((50, 3), (200, 15), (10, 15), (1, 5)):
    x = np.round(rng.standard_normal(n) * 10, 2)
    filters["medfilt"].append(dict(k=k, x=x.tolist(), y=sig.medfilt(x, k).tolist()))
    filters["median_nearest"].append(dict(k=k, x=x.tolist(),
                                          y=median_filter(x, size=k, mode="nearest").tolist()))
(OUT / "filters.json").write_text(json.dumps(filters))
(OUT / "mel_cases.json").write_text(json.dumps(cases, indent=1))
(OUT / "versions.json").write_text(json.dumps(dict(librosa=librosa.__version__,
                                                   scipy=scipy.__version__,
                                                   numpy=np.__version__), indent=1))
print("fixtures written to", OUT)

# Small encoded audio files for the decoder tests: 0.5 s of A4 (440 Hz) at 0.5 amplitude.
import soundfile as sf  # noqa: E402

AUDIO = OUT / "audio"
AUDIO.mkdir(exist_ok=True)
for sr, channels, fmt, subtype, ext in (
    (22050, 1, "FLAC", "PCM_16", "flac"),
    (44100, 2, "OGG", "VORBIS", "ogg"),
    (44100, 1, "MP3", "MPEG_LAYER_III", "mp3"),
    (48000, 2, "WAV", "PCM_24", "wav"),
    (16000, 1, "WAV", "FLOAT", "f32.wav"),
):
    t = np.arange(int(sr * 0.5)) / sr
    tone = 0.5 * np.sin(2 * np.pi * 440.0 * t)
    data = np.stack([tone] * channels, axis=1) if channels > 1 else tone
    sf.write(AUDIO / f"a440_{sr}_{channels}ch.{ext}", data, sr, format=fmt, subtype=subtype)
print("audio fixtures written to", AUDIO)
