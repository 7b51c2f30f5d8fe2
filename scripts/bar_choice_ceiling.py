#!/usr/bin/env python3
"""How much of beat-net's metre and tempo-level errors a better choice among the bar-pointer
decoder's readings could fix, and whether a choice learned from what the performance holds
does.

    cargo run --release -p violin-train --example beat_candidates -- CORPUS cands.jsonl
    python3 scripts/bar_choice_ceiling.py CORPUS cands.jsonl [--with-labels] [--parity]

`beat_candidates` writes, for every training and validation item, each reading the decoder
could give (each bar length decoded on its own; every other beat of the 2- and 4-beat paths;
a beat between each two of the 1- and 2-beat paths) with its features from the activations
and its scores. This script prints, per split and for works and études apart, beat F /
downbeat F / metre / tempo of

* the reading the shipped decoder picks (log-probability plus the bar-length prior);
* the best reading (the ceiling of any choice);
* the reading a softmax over the readings picks, its weights fitted on the training split to
  maximise the expected (mean of beat and downbeat F) + metre + tempo, L2 penalties 1e-4,
  1e-3, 1e-2 (L-BFGS), on the activation features alone or, with `--with-labels`, also on
  features from the *labelled* notes and bow changes (where the readings' downbeats and
  beats fall on note onsets and bow changes, notes per beat, the length of notes starting on
  downbeats): an upper bound on what a transcription could add; with `--parity`, also the
  share of consecutive downbeats (and beats) an even number of *labelled* bow changes apart
  (the same bow direction: players hook strokes so that bars start down-bow), alone and per
  bar length. `--parity` also prints the decoder's own choice with that share added to each
  bar length's score (log-probability per frame + prior + w × share, w = 0 … 0.08), from
  the labelled bow changes or, with `--analysed DIR`, from those of `violin-skeleton
  analyze` outputs in DIR (named after the item folder, `items_00012.json`; validation only).

The test split is never read.
"""
import json
import os
import sys

import numpy as np
from scipy.optimize import minimize

from corpus_items import DECODER_PRIOR, shipped_choice

KINDS = ["decoded", "half", "double"]
PARITY = "--parity" in sys.argv
MEASURES = ["beat_f", "downbeat_f", "metre_ok", "tempo_ok"]


def near_share(times, events, tol=0.05):
    if len(times) == 0 or len(events) == 0:
        return 0.0
    ev = np.sort(np.asarray(events))
    t = np.asarray(times)
    i = np.searchsorted(ev, t)
    d = np.full(len(t), 9.0)
    ok = i < len(ev)
    d[ok] = np.abs(ev[i[ok]] - t[ok])
    ok = i > 0
    d[ok] = np.minimum(d[ok], np.abs(ev[i[ok] - 1] - t[ok]))
    return float(np.mean(d < tol))


def label_features(c, bows, notes):
    b = np.asarray(c["beats_s"])
    down = np.asarray(c["downbeats_s"])
    if len(b) < 2:
        return [0.0] * 8
    is_down = np.array([np.any(np.abs(down - t) < 1e-6) for t in b])
    other = b[~is_down]
    mids = [(x + y) / 2 for x, y in zip(b[:-1], b[1:]) if y - x < 2]
    on, dur = notes[:, 0], notes[:, 1] - notes[:, 0]

    def length_at(ts):
        v = [dur[np.argmin(np.abs(on - t))] for t in ts if len(on) and np.min(np.abs(on - t)) < 0.05]
        return float(np.mean(v)) if v else 0.0

    per_beat = np.sum((on >= b[0]) & (on <= b[-1])) / max(len(b) - 1, 1)
    median = np.median(dur) if len(dur) else 1.0
    return [near_share(down, bows), near_share(other, bows), near_share(mids, bows),
            near_share(down, on), near_share(other, on), near_share(mids, on),
            np.log2(max(per_beat, 0.1)), (length_at(down) - length_at(other)) / max(median, 1e-3)]


def parity_features(c, bows):
    """Share of consecutive downbeats (and beats) an even number of bow changes apart: the
    same bow direction, as players hook strokes so that bars start down-bow."""
    out = []
    for ts in (np.asarray(c["downbeats_s"]), np.asarray(c["beats_s"])):
        if len(ts) < 2 or len(bows) == 0:
            out.append(0.5)
            continue
        n = np.searchsorted(bows, ts + 0.05)
        out.append(float(np.mean(np.diff(n) % 2 == 0)))
    return out


def features(item, corpus, with_labels):
    cands = item["candidates"]
    top = max(c["log_p_per_frame"] for c in cands)
    if with_labels or PARITY:
        d = os.path.join(corpus, item["item"])
        bows = np.array([float(x) for x in open(os.path.join(d, "bowchanges.txt")) if x.strip()])
        notes = np.loadtxt(os.path.join(d, "notes.tsv"), skiprows=1, usecols=(0, 1), ndmin=2)
    rows = []
    for c in cands:
        lt = np.log2(max(c["tempo_bpm"], 1) / 100)
        bar = [float(c["bar"] == n) for n in (1, 2, 3, 4)]
        kind = [float(c["kind"] == k) for k in KINDS[1:]]
        contrast = c["down_at_down"] - c["down_at_other"]
        x = [c["log_p_per_frame"] - top] + bar + kind + [lt, lt * lt, c["act_beats"], c["act_mids"],
                                                          c["act_thirds"], c["down_at_down"],
                                                          c["down_at_other"], contrast]
        x += [n * contrast for n in bar]
        if with_labels:
            e = label_features(c, bows, notes)
            x += e + [n * (e[0] - e[1]) for n in bar] + [n * (e[3] - e[4]) for n in bar]
        if PARITY:
            pf = parity_features(c, bows)
            x += pf + [n * pf[0] for n in bar]
        rows.append(x)
    return np.array(rows, dtype=float)


def target(c):
    return (c["beat_f"] + c["downbeat_f"]) / 2 + c["metre_ok"] + c["tempo_ok"]


def objective(w, xs, ys, l2):
    f, g = 0.0, np.zeros_like(w)
    for x, y in zip(xs, ys):
        s = x @ w
        p = np.exp(s - s.max())
        p /= p.sum()
        e = p @ y
        f -= e
        g -= x.T @ (p * (y - e))
    return f / len(xs) + l2 * w @ w, g / len(xs) + 2 * l2 * w


def summary(items, chosen):
    out = []
    for etude in (False, True):
        c = [ch for ch, it in zip(chosen, items) if it["etude"] == etude]
        out.append(("études" if etude else "works", len(c),
                    " / ".join(f"{np.mean([x[k] for x in c]):.3f}" for k in MEASURES)))
    return "; ".join(f"{name} ({n}) {v}" for name, n, v in out)


def parity_in_decoder(split, corpus, analysed):
    """The decoded bar length chosen by log-probability + prior + w × downbeat parity."""
    def bows_of(it):
        if analysed is None:
            path = os.path.join(corpus, it["item"], "bowchanges.txt")
            return np.array([float(x) for x in open(path) if x.strip()])
        a = json.load(open(os.path.join(analysed, it["item"].replace("/", "_") + ".json")))
        return np.array(a["bow_changes_s"])

    for name, its in split.items():
        if analysed is not None and name != "Val":
            continue
        bows = {it["item"]: bows_of(it) for it in its}
        for w in (0, 0.005, 0.01, 0.02, 0.04, 0.08):
            chosen = [max((c for c in it["candidates"] if c["kind"] == "decoded"),
                          key=lambda c: c["log_p_per_frame"] + DECODER_PRIOR[c["prior_index"]]
                          + w * parity_features(c, bows[it["item"]])[0]) for it in its]
            print(f"decoder + {w:g} × parity, {name}: {summary(its, chosen)}")


def main():
    corpus, path = sys.argv[1], sys.argv[2]
    with_labels = "--with-labels" in sys.argv
    items = [json.loads(line) for line in open(path)]
    split = {s: [it for it in items if it["split"] == s] for s in ("Train", "Val")}
    print("beat F / downbeat F / metre / tempo within 8 %")
    for name, its in split.items():
        current = [shipped_choice(it) for it in its]
        best = [max(it["candidates"], key=target) for it in its]
        print(f"{name}: shipped choice: {summary(its, current)}")
        print(f"{name}: best reading:   {summary(its, best)}")
    if PARITY:
        analysed = sys.argv[sys.argv.index("--analysed") + 1] if "--analysed" in sys.argv else None
        parity_in_decoder(split, corpus, analysed)
        if analysed is not None:
            return
    xs = {s: [features(it, corpus, with_labels) for it in its] for s, its in split.items()}
    ys = {s: [np.array([target(c) for c in it["candidates"]]) for it in its] for s, its in split.items()}
    stacked = np.vstack(xs["Train"])
    mu, sd = stacked.mean(0), stacked.std(0) + 1e-9
    xs = {s: [(x - mu) / sd for x in v] for s, v in xs.items()}
    for l2 in (1e-4, 1e-3, 1e-2):
        best = None
        for seed in range(3):
            w0 = np.random.RandomState(seed).randn(stacked.shape[1]) * 0.01
            r = minimize(objective, w0, args=(xs["Train"], ys["Train"], l2), jac=True, method="L-BFGS-B")
            if best is None or r.fun < best.fun:
                best = r
        for s, its in split.items():
            chosen = [it["candidates"][int(np.argmax(x @ best.x))] for it, x in zip(its, xs[s])]
            print(f"learned choice, L2 {l2:g}, {s}: {summary(its, chosen)}")


if __name__ == "__main__":
    main()
