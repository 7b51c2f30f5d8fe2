#!/usr/bin/env python3
"""Reference fixtures for pitch-track's and beat-track's evaluation and onset/beat code.
Run by hand (librosa 0.11.0, mir_eval 0.8.2, numpy, scipy):

    pip install mir_eval
    python3 scripts/make_mir_eval_fixtures.py

Writes
  crates/pitch-track/tests/fixtures/mir_eval.json  melody scores (raw pitch accuracy, voicing
      recall / false alarm, overall accuracy) and note-onset P/R/F on seeded random cases;
  crates/beat-track/tests/fixtures/mir_eval.json   beat F-measure cases;
  crates/beat-track/tests/fixtures/librosa_beats.json  for a test signal defined by a formula
      (rebuilt in the Rust test): librosa's onset_strength (mean and median), onset_detect
      frames, tempo and beat_track frames (from the median envelope, as beat_track does).
"""
import json
import pathlib

import librosa
import mir_eval
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
rng = np.random.default_rng(20260611)


def melody_cases():
    cases = []
    for n, p_voiced, p_est_voiced, spread in [(200, 0.7, 0.7, 40.0), (300, 0.5, 0.8, 80.0), (150, 0.9, 0.6, 20.0), (100, 0.3, 0.3, 200.0)]:
        ref_v = rng.random(n) < p_voiced
        ref = np.where(ref_v, 220.0 * 2 ** (rng.integers(0, 24, n) / 12), 0.0)
        cents = rng.normal(0.0, spread, n)
        est_v = rng.random(n) < p_est_voiced
        guess = np.where(ref > 0, ref, 330.0) * 2 ** (cents / 1200)
        est = np.where(est_v, guess, np.where(rng.random(n) < 0.5, -guess, 0.0))
        rc, rv = mir_eval.melody.freq_to_voicing(ref)
        ec, ev = mir_eval.melody.freq_to_voicing(est)
        rcent, ecent = mir_eval.melody.hz2cents(rc), mir_eval.melody.hz2cents(ec)
        vr, vfa = mir_eval.melody.voicing_measures(rv, ev)
        cases.append({
            "reference_hz": ref.round(4).tolist(),
            "estimated_hz": est.round(4).tolist(),
            "raw_pitch_accuracy": mir_eval.melody.raw_pitch_accuracy(rv, rcent, ev, ecent),
            "voicing_recall": vr,
            "voicing_false_alarm": vfa,
            "overall_accuracy": mir_eval.melody.overall_accuracy(rv, rcent, ev, ecent),
        })
    return cases


def event_lists(n_ref, jitter, p_miss, p_extra):
    ref = np.sort(rng.uniform(0.5, 30.0, n_ref)).round(4)
    kept = ref[rng.random(n_ref) >= p_miss]
    est = kept + rng.normal(0.0, jitter, len(kept))
    extra = rng.uniform(0.5, 30.0, int(p_extra * n_ref))
    est = np.sort(np.concatenate([est, extra])).round(4)
    return ref, est


def onset_cases():
    cases = []
    for n, jitter, miss, extra in [(40, 0.02, 0.1, 0.1), (80, 0.04, 0.2, 0.3), (30, 0.06, 0.0, 0.0), (60, 0.01, 0.5, 0.5)]:
        ref, est = event_lists(n, jitter, miss, extra)
        p, r, f = mir_eval.transcription.onset_precision_recall_f1(
            np.stack([ref, ref + 0.1], axis=1), np.stack([est, est + 0.1], axis=1), onset_tolerance=0.05)
        cases.append({"reference_s": ref.tolist(), "estimated_s": est.tolist(), "precision": p, "recall": r, "f_measure": f})
    return cases


def beat_cases():
    cases = []
    for n, jitter, miss, extra in [(60, 0.03, 0.1, 0.1), (100, 0.05, 0.3, 0.2), (40, 0.08, 0.0, 0.0), (20, 0.02, 0.0, 1.0)]:
        ref, est = event_lists(n, jitter, miss, extra)
        cases.append({"reference_s": ref.tolist(), "estimated_s": est.tolist(),
                      "f_measure": mir_eval.beat.f_measure(ref, est, f_measure_threshold=0.07)})
    return cases


def test_signal(sr=22050, seconds=12.0):
    """Bowed-like tones, one every 0.4 s, pitches cycling over 7 semitones, accent every 4th.
    Mirrored exactly by `test_signal` in crates/beat-track/tests/librosa_parity.rs."""
    n = int(sr * seconds)
    t = np.arange(n, dtype=np.float64) / sr
    y = np.zeros(n)
    k = 0
    while 0.2 + 0.4 * k < seconds - 0.4:
        start = 0.2 + 0.4 * k
        f = 220.0 * 2 ** ((k * 5 % 7) / 12)
        amp = 0.6 if k % 4 == 0 else 0.3
        m = (t >= start) & (t < start + 0.38)
        tt = t[m] - start
        env = amp * (1 - np.exp(-tt / 0.01)) * np.exp(-tt / 0.3)
        y[m] += env * (np.sin(2 * np.pi * f * tt) + 0.5 * np.sin(4 * np.pi * f * tt) + 0.25 * np.sin(6 * np.pi * f * tt))
        k += 1
    return y.astype(np.float32)


def librosa_beats():
    sr = 22050
    y = test_signal(sr)
    mean = librosa.onset.onset_strength(y=y, sr=sr)
    median = librosa.onset.onset_strength(y=y, sr=sr, aggregate=np.median)
    onsets = librosa.onset.onset_detect(onset_envelope=mean, sr=sr)
    tempo = librosa.feature.tempo(onset_envelope=median, sr=sr)[0]
    _, beats = librosa.beat.beat_track(onset_envelope=median, sr=sr)
    return {
        "librosa": librosa.__version__,
        "sample_rate": sr,
        "onset_strength_mean": mean.astype(float).round(6).tolist(),
        "onset_strength_median": median.astype(float).round(6).tolist(),
        "onset_frames": onsets.tolist(),
        "tempo_bpm": float(tempo),
        "beat_frames": beats.tolist(),
    }


def write(path, obj):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(obj, separators=(",", ":")))
    print(f"wrote {path.relative_to(ROOT)} ({path.stat().st_size} bytes)")


if __name__ == "__main__":
    versions = {"mir_eval": mir_eval.__version__, "librosa": librosa.__version__, "numpy": np.__version__}
    write(ROOT / "crates/pitch-track/tests/fixtures/mir_eval.json",
          {"versions": versions, "melody": melody_cases(), "onsets": onset_cases()})
    write(ROOT / "crates/beat-track/tests/fixtures/mir_eval.json", {"versions": versions, "beats": beat_cases()})
    write(ROOT / "crates/beat-track/tests/fixtures/librosa_beats.json", librosa_beats())
