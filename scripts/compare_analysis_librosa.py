#!/usr/bin/env python3
"""Accuracy and speed of `violin-skeleton analyze` against librosa on the same synthetic
violin files, in one run, scored with mir_eval.

    cargo build --release -p violin-skeleton-cli -p beat-track --example write_synth
    python3 scripts/compare_analysis_librosa.py [--dir /tmp/vs-synth] [--count 8] [--seconds 30]

Steps: `write_synth` renders COUNT labelled pieces (seeds 1..COUNT, `SynthConfig::varied`:
60–160 bpm, 2/4, 3/4, 4/4 or 6/8, vibrato, slurs, repeated notes, rests) plus a 180 s piece;
each piece is analysed by `violin-skeleton analyze` and by librosa 0.11
(`pyin(fmin=185, fmax=3600, hop_length=256)` with frame_length 1024 (ours) and 2048
(librosa's default), `onset.onset_detect`, `beat.beat_track`); mir_eval 0.8 scores raw pitch
accuracy and voicing (reference f0 on the same 256-sample grid), note-onset F (±50 ms; for
librosa the onsets of `onset_detect`, it has no note segmentation), beat F and downbeat F
(±70 ms; librosa has no downbeat tracker). Speed: the 180 s piece, librosa calls timed in
this interpreter (best of 3 after a warm-up) against the stage timings printed by the CLI
(best of 3 process runs), also with RAYON_NUM_THREADS=1 (one thread against librosa's one).
"""
import argparse
import json
import os
import pathlib
import re
import subprocess
import time

import librosa
import mir_eval
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
CLI = ROOT / "target" / "release" / "violin-skeleton"
WRITE_SYNTH = ROOT / "target" / "release" / "examples" / "write_synth"
SR = 22050
HOP = 256


def melody(ref_hz, est_hz):
    n = min(len(ref_hz), len(est_hz))
    ref = np.asarray(ref_hz[:n], dtype=float)
    est = np.nan_to_num(np.asarray(est_hz[:n], dtype=float))
    ref_c, ref_v = mir_eval.melody.freq_to_voicing(ref)
    est_c, est_v = mir_eval.melody.freq_to_voicing(est)
    ref_cent = mir_eval.melody.hz2cents(ref_c)
    est_cent = mir_eval.melody.hz2cents(est_c)
    rpa = mir_eval.melody.raw_pitch_accuracy(ref_v, ref_cent, est_v, est_cent)
    vr, vfa = mir_eval.melody.voicing_measures(ref_v, est_v)
    return rpa, vr, vfa


def onset_f(ref_onsets, est_onsets):
    ref = np.asarray(ref_onsets, dtype=float)
    est = np.asarray(est_onsets, dtype=float)
    if len(ref) == 0 or len(est) == 0:
        return 0.0
    return mir_eval.onset.f_measure(ref, est, window=0.05)[0]


def beat_f(ref, est):
    ref = np.asarray(ref, dtype=float)
    est = np.asarray(est, dtype=float)
    if len(ref) == 0 or len(est) == 0:
        return 0.0
    return mir_eval.beat.f_measure(ref, est, f_measure_threshold=0.07)


def run_cli(wav, out, env=None):
    res = subprocess.run([str(CLI), "analyze", str(wav), "-o", str(out)], capture_output=True, text=True, check=True, env=env)
    stages = dict((k, float(v)) for k, v in re.findall(r"(\w[\w +]*?) ([\d.]+) ms", res.stderr))
    return json.loads(out.read_text()), stages


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dir", default="/tmp/vs-synth")
    ap.add_argument("--count", type=int, default=8)
    ap.add_argument("--seconds", type=float, default=30.0)
    args = ap.parse_args()
    d = pathlib.Path(args.dir)
    subprocess.run([str(WRITE_SYNTH), str(d), str(args.count), str(args.seconds), "180"], check=True, capture_output=True)

    rows = {k: [] for k in ["ours", "librosa_1024", "librosa_2048"]}
    print(f"{'file':10} {'truth':>10} | {'RPA ours':>8} {'lib1024':>8} {'lib2048':>8} | {'VR ours':>7} {'VFA ours':>8} {'VR lib':>7} {'VFA lib':>7} | {'onsetF ours':>11} {'lib':>6} | {'beatF ours':>10} {'lib':>6} | {'downF ours':>10}")
    for seed in range(1, args.count + 1):
        wav = d / f"synth_{seed}.wav"
        truth = json.loads((d / f"synth_{seed}.json").read_text())
        ours, _ = run_cli(wav, d / f"analysis_{seed}.json")
        y, _ = librosa.load(wav, sr=SR)
        ref_f0 = truth["f0_hz"]
        ref_on = [n["onset_s"] for n in truth["notes"]]
        r_ours = melody(ref_f0, ours["f0"]["hz"])
        libs = {}
        for fl in (1024, 2048):
            f0, _, _ = librosa.pyin(y, fmin=185, fmax=3600, sr=SR, frame_length=fl, hop_length=HOP)
            libs[fl] = melody(ref_f0, f0)
        lib_on = librosa.onset.onset_detect(y=y, sr=SR, units="time")
        _, lib_beats = librosa.beat.beat_track(y=y, sr=SR, units="time")
        on_ours = onset_f(ref_on, [n["onset_s"] for n in ours["notes"]])
        on_lib = onset_f(ref_on, lib_on)
        bf_ours = beat_f(truth["beats_s"], ours["beats_s"])
        bf_lib = beat_f(truth["beats_s"], lib_beats)
        df_ours = beat_f(truth["downbeats_s"], ours["downbeats_s"])
        meter = f"{truth['beats_per_bar'] * (3 if truth['subdivisions'] == 3 else 1)}/{8 if truth['subdivisions'] == 3 else 4}"
        print(f"synth_{seed:<4} {truth['tempo_bpm']:5.0f} {meter:>4} | {r_ours[0]:8.4f} {libs[1024][0]:8.4f} {libs[2048][0]:8.4f} | {r_ours[1]:7.3f} {r_ours[2]:8.3f} {libs[2048][1]:7.3f} {libs[2048][2]:7.3f} | {on_ours:11.3f} {on_lib:6.3f} | {bf_ours:10.3f} {bf_lib:6.3f} | {df_ours:10.3f}")
        rows["ours"].append((r_ours[0], on_ours, bf_ours, df_ours))
        rows["librosa_1024"].append((libs[1024][0], on_lib, bf_lib, float("nan")))
        rows["librosa_2048"].append((libs[2048][0], on_lib, bf_lib, float("nan")))
    print()
    print(f"{'mean':22} {'raw pitch acc':>14} {'note onset F':>13} {'beat F':>8} {'downbeat F':>11}")
    for name, r in rows.items():
        m = np.nanmean(np.array(r, dtype=float), axis=0) if name == "ours" else np.array(r, dtype=float).mean(axis=0)
        down = f"{m[3]:11.3f}" if name == "ours" else f"{'n/a':>11}"
        print(f"{name:22} {m[0]:14.4f} {m[1]:13.3f} {m[2]:8.3f} {down}")

    # Speed on 180 s.
    long_wav = d / "synth_long.wav"
    y, _ = librosa.load(long_wav, sr=SR)

    def best(fn, k=3):
        fn()
        times = []
        for _ in range(k):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        return min(times)

    t_pyin_2048 = best(lambda: librosa.pyin(y, fmin=185, fmax=3600, sr=SR, frame_length=2048, hop_length=HOP), k=1)
    t_pyin_1024 = best(lambda: librosa.pyin(y, fmin=185, fmax=3600, sr=SR, frame_length=1024, hop_length=HOP), k=1)
    t_beat = best(lambda: librosa.beat.beat_track(y=y, sr=SR))
    stage_runs = [run_cli(long_wav, d / "analysis_long.json")[1] for _ in range(3)]
    t_pitch = min(s["pitch"] for s in stage_runs) / 1e3
    t_beats = min(s["beats"] for s in stage_runs) / 1e3
    t_total = min(s["total"] for s in stage_runs) / 1e3
    one = dict(os.environ, RAYON_NUM_THREADS="1")
    single = [run_cli(long_wav, d / "analysis_long.json", env=one)[1] for _ in range(3)]
    t_pitch1 = min(s["pitch"] for s in single) / 1e3
    t_beats1 = min(s["beats"] for s in single) / 1e3
    print()
    print(f"{'180 s, 22 050 Hz':40} {'librosa':>10} {'ours':>10} {'speed-up':>9}")
    print(f"{'pyin hop 256, frame 1024 (ours: same)':40} {t_pyin_1024:9.3f}s {t_pitch:9.3f}s {t_pyin_1024 / t_pitch:8.1f}x")
    print(f"{'pyin hop 256, frame 2048 (librosa def.)':40} {t_pyin_2048:9.3f}s {t_pitch:9.3f}s {t_pyin_2048 / t_pitch:8.1f}x")
    print(f"{'beat_track (ours: + metre, downbeats)':40} {t_beat:9.3f}s {t_beats:9.3f}s {t_beat / t_beats:8.1f}x")
    print(f"{'pyin, ours on one thread':40} {t_pyin_1024:9.3f}s {t_pitch1:9.3f}s {t_pyin_1024 / t_pitch1:8.1f}x")
    print(f"{'beat_track, ours on one thread':40} {t_beat:9.3f}s {t_beats1:9.3f}s {t_beat / t_beats1:8.1f}x")
    print(f"{'whole analyze command (ours)':40} {'':>10} {t_total:9.3f}s")


if __name__ == "__main__":
    main()
