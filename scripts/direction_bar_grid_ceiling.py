#!/usr/bin/env python3
"""Do stroke directions need the notated bar? (bowing-net EXPERIMENTS, rule R87.)

    pip install numpy scikit-learn
    python3 scripts/direction_bar_grid_ceiling.py CORPUS_DIR [ANALYSES_DIR ...]   # seconds

Within a run of strokes between rests (>= 0.5 s of silence) the labelled directions of the
corpus alternate exactly, so with every bow change right a direction is one bit per run, and
the bars set it (bars start down-bow). This script gives each item its *labelled* notes,
strokes and beats, and chooses the bar grid (beats per bar 1, 2, 3, 4 or 6, and which beat
starts the bar) with a gradient-boosted classifier fitted on the training items: per
candidate grid, features of the beats it makes downbeats (a note or stroke starting there,
the length of that note and stroke, a rest before it, the melodic leap into it, a local
low or high pitch, a long note ending there), against all beats and against the grid's
other phases. Each run's bit is then the parity most downbeats vote for. Per evaluation set
it prints the share of items whose grid is right and the share of labelled strokes whose
direction is right with:

* the labelled downbeats (the vote's own ceiling);
* the classifier's grid (what the notes, strokes and beats tell without the notation);
* with ANALYSES (folders of `violin-skeleton analyze` outputs named after the item folder,
  `items_00012.json`), the analysis's downbeats.

The classifier is fitted on the training split only; the other splits are scored.

    python3 scripts/direction_bar_grid_ceiling.py [--analysed-beats] [--analysed-notes] CORPUS_DIR ANALYSES_DIR ...

takes the beats and/or the notes the grid is chosen from from the analyses instead, for every
split, training included (rule R90): the strokes stay labelled (and the runs between rests come
from the labelled notes), so the learned-grid column then says what the analysis's own beats or
notes allow with every bow change right. Items without an analysis are left out; with analysed
beats a training item is left out when no candidate grid on them agrees with its labelled
downbeats on 0.8 of the beats.
"""

import bisect
import collections
import json
import os
import sys

import numpy as np
from sklearn.ensemble import HistGradientBoostingClassifier

BAR_LENGTHS = [1, 2, 3, 4, 6]
RETAKE_REST_S = 0.5  # `performance::RETAKE_REST_S`
ON_BEAT_S = 0.1


def lines(path):
    with open(path) as f:
        return [l for l in f.read().splitlines() if l.strip()]


def load(root, item):
    """Labelled notes (sorted by onset), strokes, beats and downbeats of a corpus item."""
    d = os.path.join(root, item["dir"])
    rows = [r.split("\t") for r in lines(f"{d}/notes.tsv")[1:]]
    on = np.array([float(r[0]) for r in rows])
    order = np.argsort(on, kind="stable")
    strokes = [r.split("\t") for r in lines(f"{d}/strokes.tsv")[1:]]
    return dict(
        on=on[order],
        off=np.array([float(r[1]) for r in rows])[order],
        pitch=np.array([float(r[2]) for r in rows])[order],
        strokes=[(float(r[0]), float(r[1]), r[2]) for r in strokes],
        beats=np.array([float(l.split()[0]) for l in lines(f"{d}/beats.txt")]),
        downbeats=np.array([float(l.split()[0]) for l in lines(f"{d}/downbeats.txt")]),
    )


def in_beats(t, beats):
    """Times as (fractional) beat indices, extrapolated with the first and last beat period."""
    idx = np.arange(len(beats), dtype=float)
    y = np.interp(t, beats, idx)
    y = np.where(t < beats[0], (t - beats[0]) / (beats[1] - beats[0]), y)
    return np.where(
        t > beats[-1], idx[-1] + (t - beats[-1]) / (beats[-1] - beats[-2]), y
    )


def per_beat_features(x):
    """(features, beats): what starts, ends or leaps on each beat."""
    nb = len(x["beats"])
    k = np.arange(nb)
    on = in_beats(x["on"], x["beats"])
    length = in_beats(x["off"], x["beats"]) - on
    starts = in_beats(np.array([s[0] for s in x["strokes"]]), x["beats"])

    def on_beat(times):
        j = np.searchsorted(times, k - 0.15)
        hit = np.array(
            [i < len(times) and abs(times[i] - b) <= 0.15 for i, b in zip(j, k)]
        )
        return hit, np.minimum(j, max(len(times) - 1, 0))

    note_hit, note_at = on_beat(on)
    stroke_hit, stroke_at = on_beat(starts)

    def at(values, default=0.0, hit=note_hit, index=note_at):
        return np.array(
            [values[j] if h else default for h, j in zip(hit, index)], float
        )

    p = x["pitch"]
    rest = np.concatenate([[9.0], on[1:] - (on[:-1] + length[:-1])])
    leap = np.concatenate([[0.0], np.abs(np.diff(p))])
    low = np.array(
        [p[i] <= p[max(0, i - 3) : i + 4].min() for i in range(len(p))], float
    )
    high = np.array(
        [p[i] >= p[max(0, i - 3) : i + 4].max() for i in range(len(p))], float
    )
    stroke_len = np.concatenate([np.diff(starts), [4.0]])
    long_end, _ = on_beat(np.sort((on + length)[length >= 1.0]))
    return np.array(
        [
            note_hit.astype(float),
            at(np.log2(np.maximum(length, 1e-3)), -4.0),
            at((length >= 1.0).astype(float)),
            at((length >= 2.0).astype(float)),
            stroke_hit.astype(float),
            at(np.log2(np.maximum(stroke_len, 1e-3)), -4.0, stroke_hit, stroke_at),
            at((rest > 0.1).astype(float)),
            at(leap),
            at(low),
            at(high),
            long_end.astype(float),
        ]
    )


def grid_rows(x):
    """One feature row per candidate grid (beats per bar, first downbeat), and the grids."""
    f = per_beat_features(x)
    nb = f.shape[1]
    mean = f.mean(axis=1)
    first = float(in_beats(x["on"][:1], x["beats"])[0])
    rows, grids = [], []
    for b in BAR_LENGTHS:
        phase_means = [
            f[:, np.arange(nb) % b == q].mean(axis=1) for q in range(min(b, nb))
        ]
        for q, m in enumerate(phase_means):
            others = [o for r, o in enumerate(phase_means) if r != q]
            best_other = np.max(others, axis=0) if others else mean
            first_here = float(first > -0.5 and round(first) % b == q)
            rows.append([b, q, *m, *(m - mean), *(m - best_other), first_here, nb / b])
            grids.append((b, q))
    return np.array(rows, float), grids


def true_grid(x, tolerance_s=0.03):
    """The candidate grid that agrees most with the labelled downbeats, and its agreement."""
    nb = len(x["beats"])
    down = np.array(
        [np.any(np.abs(x["downbeats"] - t) < tolerance_s) for t in x["beats"]]
    )
    scores = [
        (np.mean((np.arange(nb) % b == q) == down), (b, q))
        for b in BAR_LENGTHS
        for q in range(b)
    ]
    agreement, grid = max(scores, key=lambda s: s[0])
    return grid, agreement


def find_analysis(analyses, item):
    """The item's analysis from the first folder that has it, or None."""
    base = item["dir"].replace("/", "_") + ".json"
    for d in analyses:
        if os.path.exists(os.path.join(d, base)):
            with open(os.path.join(d, base)) as f:
                return json.load(f)
    return None


def with_analysed(x, analysis, beats, notes):
    """`x` with the analysis's beats and/or notes; strokes and downbeats stay."""
    y = dict(x)
    if beats:
        y["beats"] = np.array(analysis["beats_s"], float)
    if notes:
        found = sorted(analysis["notes"], key=lambda n: n["onset_s"])
        y["on"] = np.array([n["onset_s"] for n in found], float)
        y["off"] = np.array([n["offset_s"] for n in found], float)
        y["pitch"] = np.array([float(n["midi"]) for n in found])
    return y


def near(times, t):
    i = bisect.bisect_left(times, t - ON_BEAT_S)
    return i < len(times) and abs(times[i] - t) <= ON_BEAT_S


def directions_right(x, downbeats):
    """Labelled strokes whose direction the vote gets right: per run between rests, the
    parity most strokes starting on a downbeat have is down, and the bow alternates."""
    latest, until = -1e9, []
    for a, b in zip(x["on"], x["off"]):
        latest = max(latest, b)
        until.append(latest)
    onsets = list(x["on"])

    def rest_before(t):
        i = bisect.bisect_left(onsets, t - 1e-6)
        return t - until[i - 1] if i > 0 else 1e9

    starts = [s[0] for s in x["strokes"]]
    runs, run = [], []
    for k, t in enumerate(starts):
        if k > 0 and rest_before(t) >= RETAKE_REST_S:
            runs.append(run)
            run = []
        run.append(k)
    runs.append(run)
    downbeats = sorted(downbeats)
    right = 0
    for run in runs:
        vote = sum(
            1 if i % 2 == 0 else -1
            for i, k in enumerate(run)
            if near(downbeats, starts[k])
        )
        for i, k in enumerate(run):
            right += ((i % 2 == 0) == (vote >= 0)) == (x["strokes"][k][2] == "down")
    return right


def main():
    args = sys.argv[1:]
    analysed_beats = "--analysed-beats" in args
    analysed_notes = "--analysed-notes" in args
    args = [a for a in args if a not in ("--analysed-beats", "--analysed-notes")]
    if not args or ((analysed_beats or analysed_notes) and len(args) < 2):
        sys.exit(__doc__)
    root, analyses = args[0], args[1:]
    with open(os.path.join(root, "manifest.json")) as f:
        items = json.load(f)["items"]
    sets = collections.defaultdict(list)
    for item in items:
        x = load(root, item)
        analysis = find_analysis(analyses, item) if analyses else None
        grid_x = x
        if analysed_beats or analysed_notes:
            if analysis is None:
                continue
            grid_x = with_analysed(x, analysis, analysed_beats, analysed_notes)
        if len(grid_x["beats"]) < 4 or len(grid_x["on"]) < 4:
            continue
        truth, agreement = true_grid(grid_x, 0.07 if analysed_beats else 0.03)
        name = {"train": "train", "val": "validation"}.get(
            item["split"], item["held_out"]
        )
        if name == "train" and analysed_beats and agreement < 0.8:
            continue
        sets[name].append((x, grid_x, *grid_rows(grid_x), truth, analysis))
    features = np.concatenate([s[2] for s in sets["train"]])
    labels = np.concatenate([[g == s[4] for g in s[3]] for s in sets["train"]])
    model = HistGradientBoostingClassifier(
        max_iter=300,
        learning_rate=0.05,
        random_state=0,
        max_leaf_nodes=15,
        min_samples_leaf=100,
        l2_regularization=1.0,
    ).fit(features, labels)
    print(f"training items {len(sets['train'])}")
    print(
        "set\titems\tgrid right\tstrokes\tlabelled downbeats\tlearned grid\tanalysed downbeats"
    )
    for name in sorted(k for k in sets if k != "train"):
        n_grid = strokes = with_true = with_grid = with_analysis = analysed = 0
        for x, grid_x, rows, grids, truth, analysis in sets[name]:
            b, q = grids[int(np.argmax(model.predict_proba(rows)[:, 1]))]
            n_grid += (b, q) == truth
            strokes += len(x["strokes"])
            with_true += directions_right(x, list(x["downbeats"]))
            with_grid += directions_right(x, list(grid_x["beats"][q::b]))
            if analysis is not None:
                with_analysis += directions_right(x, analysis["downbeats_s"])
                analysed += len(x["strokes"])
        share = f"{with_analysis / analysed:.3f}" if analysed else "-"
        print(
            f"{name}\t{len(sets[name])}\t{n_grid / len(sets[name]):.3f}\t{strokes}\t"
            f"{with_true / strokes:.3f}\t{with_grid / strokes:.3f}\t{share}"
        )


if __name__ == "__main__":
    main()
