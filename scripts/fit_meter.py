#!/usr/bin/env python3
"""Fits the feature weights of beat-track's metre step (`MeterConfig`) on a corpus.

    cargo build --release -p beat-track --example level_features
    python3 scripts/fit_meter.py --corpus /work/data/corpus-mix [--splits train,val] \
        [--bow-changes DIR]

`level_features` (crates/beat-track/examples) dumps, for every item's audio, the beats the
metre step receives and their raw bar features (`BeatFeatures`: accent, level, space,
duration, change, rest, bow). Bow changes come from `--bow-changes DIR`, holding
`violin-skeleton analyze` outputs named `<manifest index>.json` (bowing-net's
`bow_changes_s`, as the facade passes them); without it the bow weight is left at 0. This script re-implements `estimate_meter` (z-scored features,
weighted sum, one-way ANOVA per hypothesis, BIC, ordered label means) — it first checks
that, under the current weights, it picks the same downbeats as the Rust code on every item —
and then searches the weights (coordinate search over multiplicative steps, from the
current ones; the BIC's choice does not depend on the weights' common scale, so `accent`
stays at 1) for the highest mean downbeat F-measure (mir_eval, ±70 ms). Printed: the
5-fold cross-validated downbeat F (folds over items, seed 1) of the search, and the weights
found on all selected items.

The test split is never read unless `--splits` names it.
"""
import argparse
import math
import pathlib

import mir_eval
import numpy as np

from fitting import dump_level_features, five_fold_cv

FEATURES = ["accent", "level", "space", "duration", "change", "rest", "bow"]
# MeterConfig::default(): accent, level, space, duration, change, rest, bow weights.
CURRENT = [1.0, 0.0, 0.0, 0.262, 0.0, 0.5, 1.0]
SUBDIVISION_MIN_BPM = 130.0
SUBDIVISION_PENALTY = 1.0


def load(corpus, splits, bow_dir=None):
    items, dumps = dump_level_features(corpus, splits, bow_dir)
    data = []
    for it, d in zip(items, dumps):
        if not d["level_beats_s"] or len(d["level_beats_s"]) < 4:
            continue
        beats = np.array(d["level_beats_s"])
        n = len(beats)
        z = []
        for name in FEATURES:
            f = np.array(d["bar_features"].get(name, []), dtype=float)
            if len(f) != n:
                z.append(np.zeros(n))
                continue
            sd = f.std()
            z.append((f - f.mean()) / sd if sd > 1e-12 else np.zeros(n))
        ref = np.loadtxt(corpus / it["dir"] / "downbeats.txt", ndmin=1)
        data.append(dict(beats=beats, z=np.array(z), tempo=d["level_tempo_bpm"], ref=ref,
                         rust=np.array(d["downbeats_s"]), hyps=hypotheses(n, d["level_tempo_bpm"])))
    return data


def hypotheses(n, tempo):
    """(labels per beat, number of labels, is-subdivision, period, phase) as estimate_meter."""
    out = []
    spec = [(m, 1, ph) for m in (4, 3, 2) for ph in range(m)]
    if tempo >= SUBDIVISION_MIN_BPM:
        spec += [(m, 2, ph) for m in (4, 3, 2) for ph in range(2 * m)]
        spec += [(2, 3, ph) for ph in range(6)]
    i = np.arange(n)
    for m, sub, ph in spec:
        period = m * sub
        if n < 2 * period:
            continue
        pos = (i + period - ph % period) % period
        labels = np.where(pos == 0, 0, np.where(pos % sub == 0, 1, 2))
        out.append((labels, 2.0 if sub == 1 else 3.0, sub > 1, period, ph % period))
    return out


def downbeats(item, w):
    s = np.asarray(w) @ item["z"]
    n = len(s)
    best = None
    for labels, k, is_sub, period, phase in item["hyps"]:
        means = [s[labels == g].mean() if np.any(labels == g) else 0.0 for g in range(3)]
        if means[0] < means[1] or (is_sub and means[1] < means[2]):
            continue
        rss = max(float(((s - np.take(means, labels)) ** 2).sum()), 1e-12 * n)
        bic = n * math.log(rss / n) + k * math.log(n)
        if is_sub:
            bic += SUBDIVISION_PENALTY * math.log(n)
        if best is None or bic < best[0]:
            best = (bic, period, phase)
    if best is None:
        return item["beats"][:1]
    return item["beats"][best[2]::best[1]]


def mean_f(data, w):
    return float(np.mean([mir_eval.beat.f_measure(d["ref"], downbeats(d, w)) for d in data]))


def search(data, start, rounds=3):
    w = list(start)
    best = mean_f(data, w)
    for _ in range(rounds):
        improved = False
        for j in range(1, len(w)):
            for factor in (0.0, 0.5, 0.75, 1.33, 2.0):
                trial = list(w)
                trial[j] = w[j] * factor if w[j] != 0 else (0.5 if factor > 1 else 0.0)
                f = mean_f(data, trial)
                if f > best + 1e-9:
                    best, w, improved = f, trial, True
        if not improved:
            break
    return w, best


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--corpus", type=pathlib.Path, required=True)
    ap.add_argument("--splits", default="train,val")
    ap.add_argument("--bow-changes", type=pathlib.Path, default=None)
    args = ap.parse_args()
    data = load(args.corpus, set(args.splits.split(",")), args.bow_changes)
    same = sum(len(d["rust"]) == len(downbeats(d, CURRENT)) and np.allclose(d["rust"], downbeats(d, CURRENT))
               for d in data)
    print(f"{len(data)} items of {args.splits}; this script and estimate_meter agree on {same}")
    print(f"downbeat F, current weights: {mean_f(data, CURRENT):.3f}")
    cv = five_fold_cv(data, lambda part: search(part, CURRENT)[0], mean_f)
    print(f"5-fold CV downbeat F of the search: {cv:.3f}")
    w, f = search(data, CURRENT)
    print(f"weights found on all items (downbeat F {f:.3f}):")
    for name, v in zip(FEATURES, w):
        print(f"  {name}_weight: {v:.3f},")


if __name__ == "__main__":
    main()
