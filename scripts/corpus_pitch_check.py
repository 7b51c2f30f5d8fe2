#!/usr/bin/env python3
"""Listen-free realism check of rendered corpus audio: librosa's pyin against the labels.

    python3 scripts/corpus_pitch_check.py DIR [DIR ...]

Each DIR holds `audio.wav` (or `audio.mp3` / `audio.ogg`, mono or stereo: mixed down) and
`notes.tsv` (onset_s, offset_s, midi, ...). Frames within 30 ms of a note's onset or end are
not scored ("away from onsets"). Prints the raw pitch
accuracy (share of labelled-voiced frames whose pyin f0 is within 50 cents of the label; an
unvoiced estimate counts as wrong) and the voicing recall, pooled over all DIRs.
"""
import glob
import sys

import librosa
import numpy as np

HOP = 256


def check(d):
    audio = sorted(glob.glob(f"{d}/audio.*"))[0]
    y, sr = librosa.load(audio, sr=22050, mono=True)
    f0, voiced, _ = librosa.pyin(y, fmin=185, fmax=3600, sr=sr, frame_length=2048, hop_length=HOP)
    t = librosa.times_like(f0, sr=sr, hop_length=HOP)
    ref = np.zeros_like(f0)
    for line in open(f"{d}/notes.tsv"):
        if line.startswith("onset"):
            continue
        on, off, midi = line.split("\t")[:3]
        ref[(t >= float(on) + 0.03) & (t < float(off) - 0.03)] = librosa.midi_to_hz(int(midi))
    mask = ref > 0
    est = np.where(voiced, f0, 0.0)
    ok = (est[mask] > 0) & (np.abs(1200 * np.log2(np.maximum(est[mask], 1e-9) / ref[mask])) <= 50)
    return ok.sum(), mask.sum(), (est[mask] > 0).sum(), len(y) / sr


tot_ok = tot = tot_v = secs = 0
for d in sys.argv[1:]:
    ok, n, v, s = check(d)
    print(f"{d}: raw pitch accuracy {ok / n:.3f} over {n} frames ({s:.1f} s)")
    tot_ok += ok
    tot += n
    tot_v += v
    secs += s
print(f"pooled: raw pitch accuracy {tot_ok / tot:.3f}, voicing recall {tot_v / tot:.3f}, {secs:.0f} s of audio")
