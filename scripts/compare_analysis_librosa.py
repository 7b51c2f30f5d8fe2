#!/usr/bin/env python3
"""Accuracy and speed of our pitch/beat analysis against librosa on the same files, in one
run, scored with mir_eval.

    cargo build --release -p beat-track --example analyze_files --example write_synth
    # synthetic pieces (labelled by construction) + speed on a 180 s piece:
    python3 scripts/compare_analysis_librosa.py [--dir /tmp/vs-synth] [--count 8] [--seconds 30]
    # the corpus (both renderers), accuracy only:
    python3 scripts/compare_analysis_librosa.py --corpus /work/data/corpus-mix [--split test]

Ours: `analyze_files` (crates/beat-track/examples) makes exactly the calls of
`Pipeline::analyze` — `PitchTracker` (pYIN, frame 1024, hop 256), `segment_notes`,
`BeatTracker::track` with the notes — on audio decoded and resampled to 22 050 Hz by
`dsp_mel`, and reports each stage's time. librosa 0.11: `pyin(fmin=185, fmax=3600,
hop_length=256)` with frame_length 1024 (ours) and 2048 (librosa's default),
`onset.onset_detect`, `beat.beat_track` on `librosa.load(sr=22050)`. mir_eval 0.8 scores raw
pitch accuracy and voicing (±50 cents, f0 on the same 256-sample grid), note-onset F (±50 ms;
for librosa the onsets of `onset_detect`: it has no note segmentation), beat F and downbeat F
(±70 ms; librosa has no downbeat tracker). Each metric is computed per file and averaged.

Synthetic pieces (`write_synth`) are corpus études rendered by the built-in bowed-string
synthesizer without augmentation; their truth JSON carries the pitch reference and the frames
to score (`f0_keep`, the same rule as below). Corpus references come from each item's
`notes.tsv` (pitch = MIDI note shifted by the item's `tuning_cents`; vibrato stays within
±25 cents of it), `beats.txt` and `downbeats.txt`. Frames the labels cannot decide are left
out of the pitch scores: within 30 ms of a note's onset or offset (slur glides last 25 ms;
attacks and releases), and from a note's offset to 0.2 s after it (release and reverb tail,
which the corpus does not label) unless another note sounds.

Speed (synthetic mode): the 180 s piece, decoding excluded on both sides (librosa's calls get
the loaded array; ours are timed after `dsp_mel` decoded and resampled), best of 3 after a
warm-up for librosa, best of 5 in one process for ours, also with RAYON_NUM_THREADS=1 (one
thread against librosa's one). Run it under `flock /tmp/cpu-timing.lock` and note `uptime`.
"""
import argparse
import json
import os
import pathlib
import subprocess
import time

import librosa
import mir_eval
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
ANALYZE = ROOT / "target" / "release" / "examples" / "analyze_files"
WRITE_SYNTH = ROOT / "target" / "release" / "examples" / "write_synth"
SR = 22050
HOP = 256
EDGE_S = 0.03
TAIL_S = 0.2


def melody(ref_hz, est_hz, keep=None):
    n = min(len(ref_hz), len(est_hz))
    ref = np.asarray(ref_hz[:n], dtype=float)
    est = np.nan_to_num(np.asarray(est_hz[:n], dtype=float))
    if keep is not None:
        ref, est = ref[keep[:n]], est[keep[:n]]
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


def run_ours(files, out_dir, repeat=1, env=None):
    """Analyses every file in one process; returns the parsed JSONs in order."""
    out_dir = pathlib.Path(out_dir)
    cmd = [str(ANALYZE), str(out_dir), "--repeat", str(repeat)] + [str(f) for f in files]
    subprocess.run(cmd, check=True, capture_output=True, text=True, env=env)
    return [json.loads((out_dir / f"{i}.json").read_text()) for i in range(len(files))]


def corpus_reference(item_dir, tuning_cents, n_frames):
    """Reference f0 (Hz, 0 = unvoiced) on the hop grid, the frames to score, note onsets."""
    notes = []
    for line in (item_dir / "notes.tsv").read_text().splitlines()[1:]:
        on, off, midi = line.split("\t")[:3]
        notes.append((float(on), float(off), int(midi)))
    t = np.arange(n_frames) * HOP / SR
    ref = np.zeros(n_frames)
    keep = np.ones(n_frames, dtype=bool)
    sounding = np.zeros(n_frames, dtype=bool)
    for on, off, _ in notes:
        sounding |= (t >= on - EDGE_S) & (t < off + EDGE_S)
    for on, off, midi in notes:
        inside = (t >= on + EDGE_S) & (t < off - EDGE_S)
        ref[inside] = librosa.midi_to_hz(midi) * 2.0 ** (tuning_cents / 1200.0)
        keep &= ~((t >= on - EDGE_S) & (t < on + EDGE_S))
        keep &= ~((t >= off - EDGE_S) & (t < off + EDGE_S))
        keep &= ~((t >= off) & (t < off + TAIL_S) & ~sounding)
    return ref, keep, [n[0] for n in notes]


def audible_onsets(item_dir):
    """The labelled onsets minus same-pitch slurred ones: a note slurred (no bow change) from a
    note of the same pitch that it touches. Corpora written before 2026-11-21 rendered it as
    one unbroken tone (same key, same stroke, no glide), so nothing in their audio marks its
    onset; newer corpora play it portato (a dip and swell), and there this figure only leaves
    out the portato notes."""
    perf = json.loads((item_dir / "performance.json").read_text())
    notes, bows = perf["notes"], np.asarray(perf["bow_changes_s"], dtype=float)
    out = []
    for k, n in enumerate(notes):
        if k > 0:
            prev = notes[k - 1]
            bowed = len(bows) > 0 and np.min(np.abs(bows - n["onset_s"])) < 1e-3
            if prev["midi"] == n["midi"] and n["onset_s"] - prev["offset_s"] < 1e-3 and not bowed:
                continue
        out.append(n["onset_s"])
    return out


def read_times(path):
    return [float(x) for x in path.read_text().split()]


SKIP_LIBROSA = False


def librosa_scores(y, ref_f0, keep, ref_on, ref_beats):
    if SKIP_LIBROSA:
        nan = (float("nan"),) * 3
        return {1024: nan, 2048: nan}, float("nan"), float("nan")
    libs = {}
    for fl in (1024, 2048):
        f0, _, _ = librosa.pyin(y, fmin=185, fmax=3600, sr=SR, frame_length=fl, hop_length=HOP)
        libs[fl] = melody(ref_f0, f0, keep)
    lib_on = librosa.onset.onset_detect(y=y, sr=SR, units="time")
    _, lib_beats = librosa.beat.beat_track(y=y, sr=SR, units="time")
    return libs, onset_f(ref_on, lib_on), beat_f(ref_beats, lib_beats)


HEADER = (f"{'file':12} {'truth':>10} {'ours':>10} | {'RPA ours':>8} {'lib1024':>8} {'lib2048':>8} | "
          f"{'VR ours':>7} {'VFA ours':>8} {'VR lib':>7} {'VFA lib':>7} | {'onsetF ours':>11} {'lib':>6} | "
          f"{'beatF ours':>10} {'lib':>6} | {'downF ours':>10}")


def meter_name(beats_per_bar, subdivisions):
    return f"{beats_per_bar * 3}/8" if subdivisions == 3 else f"{beats_per_bar}/4"


def score_one(name, truth_label, ours, y, ref_f0, keep, ref_on, ref_beats, ref_down, ref_on_audible=None):
    r_ours = melody(ref_f0, ours["f0_hz"], keep)
    libs, on_lib, bf_lib = librosa_scores(y, ref_f0, keep, ref_on, ref_beats)
    on_ours = onset_f(ref_on, [n["onset_s"] for n in ours["notes"]])
    ref_aud = ref_on if ref_on_audible is None else ref_on_audible
    on_ours_aud = onset_f(ref_aud, [n["onset_s"] for n in ours["notes"]])
    on_lib_aud = float("nan") if SKIP_LIBROSA else onset_f(
        ref_aud, librosa.onset.onset_detect(y=y, sr=SR, units="time"))
    bf_ours = beat_f(ref_beats, ours["beats_s"])
    df_ours = beat_f(ref_down, ours["downbeats_s"])
    ours_label = f"{ours['tempo_bpm']:5.0f} {meter_name(*ours['meter']):>4}"
    print(f"{name:12} {truth_label:>10} {ours_label:>10} | {r_ours[0]:8.4f} {libs[1024][0]:8.4f} {libs[2048][0]:8.4f} | "
          f"{r_ours[1]:7.3f} {r_ours[2]:8.3f} {libs[2048][1]:7.3f} {libs[2048][2]:7.3f} | {on_ours:11.3f} {on_lib:6.3f} | "
          f"{bf_ours:10.3f} {bf_lib:6.3f} | {df_ours:10.3f}", flush=True)
    return {
        "ours": (r_ours[0], r_ours[1], r_ours[2], on_ours, bf_ours, df_ours, on_ours_aud),
        "librosa_1024": (libs[1024][0], libs[1024][1], libs[1024][2], on_lib, bf_lib, float("nan"), on_lib_aud),
        "librosa_2048": (libs[2048][0], libs[2048][1], libs[2048][2], on_lib, bf_lib, float("nan"), on_lib_aud),
    }


def print_means(title, rows):
    print(f"\n{title}")
    print(f"{'':22} {'raw pitch acc':>14} {'voicing rec':>12} {'voicing FA':>11} {'note onset F':>13} {'beat F':>8} {'downbeat F':>11} {'onset F, audible¹':>18}")
    for name in ["ours", "librosa_1024", "librosa_2048"]:
        r = np.array([x[name] for x in rows], dtype=float)
        m = r.mean(axis=0)
        down = f"{m[5]:11.3f}" if name == "ours" else f"{'n/a':>11}"
        print(f"{name:22} {m[0]:14.4f} {m[1]:12.3f} {m[2]:11.3f} {m[3]:13.3f} {m[4]:8.3f} {down} {m[6]:18.3f}")


AUDIBLE_NOTE = ("¹ onset F against the labelled onsets minus same-pitch slurred ones (inaudible in "
                "corpora written before the portato rendering of 2026-11-21; see audible_onsets); "
                "the main figure keeps every labelled onset.")


def corpus_mode(args):
    root = pathlib.Path(args.corpus)
    manifest = json.loads((root / "manifest.json").read_text())
    splits = args.split.split(",")
    items = [it for it in manifest["items"] if it["split"] in splits]
    if args.renderer:
        items = [it for it in items if it["renderer"] == args.renderer]
    print(f"{root}: {len(items)} {args.split} items "
          + ", ".join(f"{r} {sum(it['renderer'] == r for it in items)}" for r in sorted({it['renderer'] for it in items})))
    ours_all = run_ours([root / it["dir"] / "audio.wav" for it in items], pathlib.Path(args.dir) / "corpus")
    print(HEADER)
    by_renderer = {}
    for it, ours in zip(items, ours_all):
        d = root / it["dir"]
        y, _ = librosa.load(d / "audio.wav", sr=SR)
        n_frames = 1 + len(y) // HOP
        ref_f0, keep, ref_on = corpus_reference(d, it["augmentation"]["tuning_cents"], n_frames)
        truth = f"{it['tempo_bpm']:5.0f} {it['meter']:>4}"
        name = f"{it['id']:05d} {it['renderer'][:2]}"
        row = score_one(name, truth, ours, y, ref_f0, keep, ref_on,
                        read_times(d / "beats.txt"), read_times(d / "downbeats.txt"),
                        audible_onsets(d))
        by_renderer.setdefault(it["renderer"], []).append(row)
    for renderer, rows in sorted(by_renderer.items()):
        print_means(f"mean over {len(rows)} {renderer} items", rows)
    print_means(f"mean over all {sum(len(r) for r in by_renderer.values())} items",
                [r for rows in by_renderer.values() for r in rows])
    print(AUDIBLE_NOTE)


def synthetic_mode(args):
    d = pathlib.Path(args.dir)
    subprocess.run([str(WRITE_SYNTH), str(d), str(args.count), str(args.seconds), "180"], check=True, capture_output=True)
    wavs = [d / f"synth_{seed}.wav" for seed in range(1, args.count + 1)]
    ours_all = run_ours(wavs, d / "ours")
    print(HEADER)
    rows = []
    for seed, ours in zip(range(1, args.count + 1), ours_all):
        truth = json.loads((d / f"synth_{seed}.json").read_text())
        y, _ = librosa.load(d / f"synth_{seed}.wav", sr=SR)
        label = f"{truth['tempo_bpm']:5.0f} {meter_name(truth['beats_per_bar'], truth['subdivisions']):>4}"
        keep = np.asarray(truth["f0_keep"], dtype=bool) if "f0_keep" in truth else None
        rows.append(score_one(f"synth_{seed}", label, ours, y, truth["f0_hz"], keep,
                              [n["onset_s"] for n in truth["notes"]], truth["beats_s"], truth["downbeats_s"]))
    print_means(f"mean over {len(rows)} synthetic pieces", rows)
    print("¹ synthetic pieces: every labelled onset is articulated (same as note onset F).")
    if not args.no_speed:
        speed(d)


def speed(d):
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

    print(f"\nload average before timing: {os.getloadavg()}")
    t_pyin_2048 = best(lambda: librosa.pyin(y, fmin=185, fmax=3600, sr=SR, frame_length=2048, hop_length=HOP), k=1)
    t_pyin_1024 = best(lambda: librosa.pyin(y, fmin=185, fmax=3600, sr=SR, frame_length=1024, hop_length=HOP), k=1)
    t_beat = best(lambda: librosa.beat.beat_track(y=y, sr=SR))
    t_onset = best(lambda: librosa.onset.onset_strength(y=y, sr=SR, aggregate=np.median))
    timing = run_ours([long_wav], d / "long", repeat=5)[0]["timing_s"]
    one = dict(os.environ, RAYON_NUM_THREADS="1")
    timing1 = run_ours([long_wav], d / "long1", repeat=5, env=one)[0]["timing_s"]
    print(f"load average after timing: {os.getloadavg()}")
    print(f"\n{'180 s, 22 050 Hz, decoding excluded':44} {'librosa':>10} {'ours':>10} {'speed-up':>9}")
    rows = [
        ("pyin hop 256, frame 1024 (ours: same)", t_pyin_1024, timing["pitch"]),
        ("pyin hop 256, frame 2048 (librosa def.)", t_pyin_2048, timing["pitch"]),
        ("beat_track (ours: + onsets, metre, downb.)", t_beat, timing["beats"]),
        ("beat_track, ours without notes", t_beat, timing["beats_only"]),
        ("pyin, ours on one thread", t_pyin_1024, timing1["pitch"]),
        ("beat_track, ours on one thread", t_beat, timing1["beats"]),
    ]
    for name, lib, ours in rows:
        print(f"{name:44} {lib:9.3f}s {ours:9.3f}s {lib / ours:8.1f}x")
    print(f"{'librosa onset_strength alone (median agg.)':44} {t_onset:9.3f}s")
    print(f"{'ours: note segmentation':44} {'':>10} {timing['notes']:9.3f}s")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dir", default="/tmp/vs-synth", help="working folder for pieces and our JSONs")
    ap.add_argument("--count", type=int, default=8)
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--no-speed", action="store_true", help="synthetic mode: skip the timing")
    ap.add_argument("--corpus", help="score the corpus at this root instead of synthetic pieces")
    ap.add_argument("--split", default="test", help="split(s) to score, comma-separated")
    ap.add_argument("--renderer", help="only items of this renderer (builtin or soundfont)")
    ap.add_argument("--ours-only", action="store_true", help="skip librosa's analysis (quick checks)")
    args = ap.parse_args()
    global SKIP_LIBROSA
    SKIP_LIBROSA = args.ours_only
    if args.corpus:
        corpus_mode(args)
    else:
        synthetic_mode(args)


if __name__ == "__main__":
    main()
