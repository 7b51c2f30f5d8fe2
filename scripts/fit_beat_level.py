#!/usr/bin/env python3
"""Fits the weights of beat-track's beat-level choice (`LevelWeights`) on a corpus.

    cargo build --release -p beat-track --example level_features
    python3 scripts/fit_beat_level.py --corpus /work/data/corpus-mix [--splits train,val] \
        [--bow-changes DIR]

`level_features` (crates/beat-track/examples) dumps, for every item's audio, each tempogram
peak `BeatTracker` tracks (tempo, beats, features, score under the current weights) and what
`track` returns. Bow changes come from `--bow-changes DIR`, holding `violin-skeleton analyze`
outputs named `<manifest index>.json`, as for `fit_meter.py`; without it the detected onsets
stand in for them, the bow-coverage feature duplicates the onset coverage, and its weight
is left at 0. Every candidate's beats are scored against the item's `beats.txt` with
mir_eval's beat F-measure (±70 ms). The weights maximise the mean over items of the expected
F-measure under a softmax over each item's candidates (features standardised over all
candidates, L2 penalty `--l2` on the standardised weights, L-BFGS). Printed:

* 5-fold cross-validated mean F of the arg-max candidate (folds over items, seed 1);
* the weights fitted on all selected items, in the raw units of `LevelFeatures` (paste them
  into `LevelWeights::default`);
* the mean F of the arg-max candidate under those weights, of the candidate the current
  build picked, of `track`'s output (after the metre step) and of the best candidate.

The test split is never read unless `--splits` names it.
"""
import argparse
import pathlib

import mir_eval
import numpy as np
from scipy.optimize import minimize

from fitting import dump_level_features, five_fold_cv

NAMES = ["ln_tempogram", "prior", "note_coverage", "onset_coverage", "note_length", "bow_coverage"]
RUST_NAMES = ["tempogram", "prior", "note_coverage", "onset_coverage", "note_length", "bow_coverage"]


def load(corpus, splits, bow_dir=None):
    items, dumps = dump_level_features(corpus, splits, bow_dir)
    names = NAMES if bow_dir is not None else NAMES[:-1]
    data = []
    for it, d in zip(items, dumps):
        ref = np.loadtxt(corpus / it["dir"] / "beats.txt", ndmin=1)
        cands = d["candidates"]
        if not cands:
            continue
        x = np.array([[c["features"][n] for n in names] for c in cands])
        f = np.array([mir_eval.beat.f_measure(ref, np.array(c["beats_s"])) for c in cands])
        current = int(np.argmax([c["score"] for c in cands]))
        out_f = mir_eval.beat.f_measure(ref, np.array(d["beats_s"]))
        data.append(dict(item=it, x=x, f=f, current=current, track_f=out_f))
    return data


def fit(data, mu, sd, l2):
    xs = [(d["x"] - mu) / sd for d in data]

    def loss(w):
        total, grad = 0.0, np.zeros_like(w)
        for x, d in zip(xs, data):
            s = x @ w
            p = np.exp(s - s.max())
            p /= p.sum()
            ef = p @ d["f"]
            total -= ef
            grad -= x.T @ (p * (d["f"] - ef))
        n = len(data)
        return total / n + l2 * w @ w, grad / n + 2 * l2 * w

    w0 = np.zeros(data[0]["x"].shape[1])
    w0[0] = 1.0
    return minimize(loss, w0, jac=True, method="L-BFGS-B").x


def chosen_f(data, w_std, mu, sd):
    return float(np.mean([d["f"][int(np.argmax(((d["x"] - mu) / sd) @ w_std))] for d in data]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--corpus", type=pathlib.Path, required=True)
    ap.add_argument("--splits", default="train,val")
    ap.add_argument("--l2", type=float, default=0.01)
    ap.add_argument("--bow-changes", type=pathlib.Path, default=None)
    args = ap.parse_args()
    data = load(args.corpus, set(args.splits.split(",")), args.bow_changes)
    allx = np.concatenate([d["x"] for d in data])
    mu, sd = allx.mean(0), allx.std(0) + 1e-9
    cv = five_fold_cv(
        data, lambda part: fit(part, mu, sd, args.l2), lambda part, w: chosen_f(part, w, mu, sd)
    )
    w = fit(data, mu, sd, args.l2)
    print(f"{len(data)} items of {args.splits}; 5-fold CV beat F {cv:.3f}")
    print("weights (raw units):")
    for name, v in zip(RUST_NAMES, list(w / sd) + [0.0]):
        print(f"  {name}: {v:.2f},")
    print(f"beat F, arg-max under the fitted weights: {chosen_f(data, w, mu, sd):.3f}")
    print(f"beat F, the current build's choice:       {np.mean([d['f'][d['current']] for d in data]):.3f}")
    print(f"beat F, track() output (after the metre): {np.mean([d['track_f'] for d in data]):.3f}")
    print(f"beat F, best candidate (oracle):          {np.mean([d['f'].max() for d in data]):.3f}")


if __name__ == "__main__":
    main()
