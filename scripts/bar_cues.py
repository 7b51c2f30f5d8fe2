#!/usr/bin/env python3
"""What the labelled performance says about where bars start, per notated time signature:
could a transcription tell a 4/4 from a 2/4 (or a 6/8 from a 3/8) where the audio-only
decoder cannot? Training and validation works only; the test split is never read.

    python3 scripts/bar_cues.py CORPUS

Three cues, all from the labels (an upper bound on what an analysis could recover):

* **Harmony**: one minus the cosine between the pitch-class histograms (duration-weighted) of
  the two beats before and the two beats after a boundary. Printed per metre: the share of
  items whose mean change is larger at bar lines than at the bar's middle beat (4/4: beat 1
  against beat 3; 3/4 and 9/8: against beats 2–3) or, for the one- and two-beat metres
  (2/2, 2/4, 3/8, 6/8), at odd than at even bar lines, and the mean size of that contrast.
  If 4/4's beat-1-against-beat-3 contrast is no larger than 2/4's odd-against-even one, the
  harmony does not tell the two bar lengths apart.
* **Bow direction**: the share of down-bows among the strokes that start on each beat of the
  bar (players hook strokes so that bars start down-bow). A mid-bar beat that is seldom a
  down-bow separates the bar length from its half, if the stroke parity can be followed.
* **Repetition**: each beat's onsets on a grid of 12 steps (with their pitches, or onsets
  alone), and the share of grid steps with an onset that agree L beats later. If a 4/4's
  patterns repeated at the bar more than at the half bar, S(4) − S(2) would be larger in 4/4
  than in 2/4: printed as the chance that a 4/4 excerpt's difference exceeds a 2/4 one's
  (0.5: no separation), and the same for 6/8 against 3/8 and 3/4 against 2/4.
"""
import collections
import json
import sys

import numpy as np

from corpus_items import column


def pc_hist(notes, a, b):
    h = np.zeros(12)
    for on, off, p in notes:
        o = min(off, b) - max(on, a)
        if o > 0:
            h[p % 12] += o
    return h


def change_at(notes, beats, k):
    t = beats[k]
    p = beats[k] - beats[k - 1]
    before, after = pc_hist(notes, t - 2 * p, t), pc_hist(notes, t, t + 2 * p)
    nb, na = np.linalg.norm(before), np.linalg.norm(after)
    return 1 - before @ after / (nb * na) if nb > 0 and na > 0 else 0.0


GRID = 12
LAGS = (1, 2, 3, 4, 8)


def repetition(notes, beats):
    """S(L) for L in LAGS, from onsets alone and with pitches (see the module doc)."""
    grid = np.zeros((len(beats) - 1, GRID), int)
    for k in range(len(beats) - 1):
        a, b = beats[k], beats[k + 1]
        for on, _, p in notes:
            if a - 0.02 <= on < b - 0.02:
                grid[k, min(int(round((on - a) / (b - a) * GRID)), GRID - 1)] = p
    out = {}
    for lag in LAGS:
        if len(grid) <= lag + 2:
            return None
        x, y = grid[:-lag], grid[lag:]
        used = (x > 0) | (y > 0)
        n = max(used.sum(), 1)
        out[lag] = (((x > 0) == (y > 0)) & used).sum() / n, ((x == y) & used).sum() / n
    return out


def separation(a, b):
    """The chance that a value of `a` exceeds one of `b` (ties count half)."""
    if not a or not b:
        return float("nan")
    return float(np.mean([(x > y) + 0.5 * (x == y) for x in a for y in b]))


def main():
    corpus = sys.argv[1]
    items = json.load(open(f"{corpus}/manifest.json"))["items"]
    harmony = collections.defaultdict(list)
    repeats = collections.defaultdict(list)
    bows = collections.defaultdict(lambda: collections.defaultdict(lambda: [0, 0]))
    for it in items:
        if "etude" in it["source"] or it["split"] == "test":
            continue
        d = f"{corpus}/{it['dir']}"
        rows = [line.split("\t") for line in open(f"{d}/notes.tsv").read().splitlines()[1:]]
        notes = [(float(r[0]), float(r[1]), int(r[2])) for r in rows]
        strokes = [line.split("\t") for line in open(f"{d}/strokes.tsv").read().splitlines()[1:]]
        beats, downs = column(f"{d}/beats.txt"), column(f"{d}/downbeats.txt")
        pos, c, bar = [], None, -1
        for b in beats:
            if any(abs(b - x) < 1e-3 for x in downs):
                c, bar = 0, bar + 1
            pos.append((c, bar))
            c = None if c is None else c + 1
        meter = it["meter"]
        rep = repetition(notes, beats)
        if rep is not None:
            repeats[meter].append(rep)
        for b, (q, n) in zip(beats, pos):
            s = [st for st in strokes if abs(float(st[0]) - b) < 0.06]
            if q is None or not s:
                continue
            key = f"beat {q + 1}" if q > 0 else "bar line"
            bows[meter][key][0] += s[0][2] == "down"
            bows[meter][key][1] += 1
        inner = [(k, pos[k]) for k in range(1, len(beats) - 1) if pos[k][0] is not None]
        if meter in ("2/2", "2/4", "3/8", "6/8"):
            a = [change_at(notes, beats, k) for k, (q, n) in inner if q == 0 and n % 2 == 0]
            b = [change_at(notes, beats, k) for k, (q, n) in inner if q == 0 and n % 2 == 1]
        elif meter == "4/4":
            a = [change_at(notes, beats, k) for k, (q, n) in inner if q == 0]
            b = [change_at(notes, beats, k) for k, (q, n) in inner if q == 2]
        elif meter in ("3/4", "9/8"):
            a = [change_at(notes, beats, k) for k, (q, n) in inner if q == 0]
            b = [change_at(notes, beats, k) for k, (q, n) in inner if q in (1, 2)]
        else:
            continue
        if len(a) >= 2 and len(b) >= 2:
            harmony[meter].append(np.mean(a) - np.mean(b))
    print("| metre | items | larger at bar lines (or odd bars) | mean abs contrast |")
    print("|---|---|---|---|")
    for meter, diffs in sorted(harmony.items()):
        x = np.array(diffs)
        print(f"| {meter} | {len(x)} | {np.mean(x > 0):.2f} | {np.mean(np.abs(x)):.3f} |")
    print()
    print("| metre | share of down-bows among strokes starting on: bar line, beat 2, 3, ... |")
    print("|---|---|")
    for meter in sorted(bows):
        shares = [f"{k} {v[0] / v[1]:.2f} ({v[1]})" for k, v in sorted(bows[meter].items())
                  if v[1] >= 20]
        print(f"| {meter} | {', '.join(shares)} |")
    print()
    print("| repetition | 4/4 vs 2/4: S(4) − S(2) | 6/8 vs 3/8: S(2) − S(1) | 3/4 vs 2/4: S(3) − S(2) |")
    print("|---|---|---|---|")
    for kind, name in ((0, "onsets"), (1, "onsets and pitches")):
        def diff(meter, hi, lo):
            return [r[hi][kind] - r[lo][kind] for r in repeats[meter]]
        cells = [separation(diff("4/4", 4, 2), diff("2/4", 4, 2)),
                 separation(diff("6/8", 2, 1), diff("3/8", 2, 1)),
                 separation(diff("3/4", 3, 2), diff("2/4", 3, 2))]
        print(f"| {name} | " + " | ".join(f"{c:.2f}" for c in cells) + " |")
    eight = [f"{m} {np.mean([r[8][1] for r in repeats[m]]):.2f}" for m in ("2/2", "2/4", "4/4")
             if repeats[m]]
    print(f"\nS(8) with pitches (exact repeats 8 beats later): {', '.join(eight)}")


if __name__ == "__main__":
    main()
