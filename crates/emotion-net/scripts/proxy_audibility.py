#!/usr/bin/env python3
"""How much of the corpus arousal proxy a 2 fps x 64-band mel spectrogram can show.

Decomposes the first version of the proxy (v1: dynamic sampled at each frame's centre +
score tempo + onset density) into its terms, and fits a gradient-boosted regressor on
hand-made features of 20 s of 2 fps mel context (train split) to predict each candidate
target on the validation split -- a model-free estimate of what is learnable from the
network's input. The test split is not used.

Usage (mel2 files from the CLI, one per item, named after the item folder):
    for d in CORPUS/items/*; do
        violin-skeleton features $d/audio.wav --kind mel2 -o MEL2/$(basename $d).npy -q
    done
    python3 proxy_audibility.py CORPUS MEL2
"""
import json
import sys

import numpy as np
from sklearn.ensemble import HistGradientBoostingRegressor


def smooth(raw):
    n = len(raw)
    return np.array([(raw[max(k - 1, 0)] + 2 * raw[k] + raw[min(k + 1, n - 1)]) / 4 for k in range(n)])


def item_targets(perf, tempo_bpm, frames):
    notes, dyn = perf["notes"], np.array(perf["dynamics"])
    on = np.array([x["onset_s"] for x in notes])
    off = np.array([x["offset_s"] for x in notes])
    t = np.arange(frames) * 0.5 + 0.25
    point = np.array([next((dyn[i] for i in range(len(on)) if on[i] <= c < off[i]), 0.0) for c in t])
    fine = np.arange(frames * 50) * 0.01
    level = np.zeros(len(fine))
    for k in range(len(on)):
        sel = (fine >= on[k]) & (fine < off[k])
        level[sel] = np.maximum(level[sel], dyn[k])
    mean_dyn = level.reshape(frames, 50).mean(1)
    dens = np.array([np.sum(np.abs(on - c) <= 1.0) / 2.0 for c in t])
    gap = np.array([point[k] == 0 and np.any((off <= t[k]) & (off > t[k] - 0.05))
                    and np.any((on > t[k]) & (on < t[k] + 0.05)) for k in range(frames)])
    terms = dict(dyn=1.8 * (point - 0.45), tempo=np.full(frames, 0.9 * (tempo_bpm - 110) / 60),
                 dens=0.5 * (dens - 3) / 3, mean_dyn=1.8 * (mean_dyn - 0.45))
    return dict(terms=terms, gap=gap, tempo=np.full(frames, tempo_bpm), density=dens, mean_dyn=mean_dyn,
                v1=smooth(np.tanh(terms["dyn"] + terms["tempo"] + terms["dens"])),
                v2=smooth(np.tanh(terms["mean_dyn"] + terms["dens"])))


def features(mel):
    frames = mel.shape[0]
    loud = 10 * np.log10(np.mean(10 ** (mel / 10), axis=1) + 1e-10)
    rows = []
    for t in range(frames):
        lo, hi = max(0, t - 10), min(frames, t + 10)
        w = mel[lo:hi]
        change = np.abs(np.diff(w, axis=0)).mean() if hi - lo > 1 else 0.0
        rows.append(np.concatenate([mel[t], w.mean(0), w.std(0),
                                    [loud[t], loud[lo:hi].max(), loud[t] - loud[lo:hi].max(), change,
                                     loud[lo:hi].std()]]))
    return np.array(rows)


def main(corpus, mel_dir):
    manifest = json.load(open(f"{corpus}/manifest.json"))
    items = []
    for it in manifest["items"]:
        if it["split"] == "test":
            continue
        name = it["dir"].split("/")[-1]
        mel = np.load(f"{mel_dir}/{name}.npy")
        perf = json.load(open(f"{corpus}/{it['dir']}/performance.json"))
        frames = min(len(perf["arousal"]["values"]), mel.shape[0])
        d = item_targets(perf, it["tempo_bpm"], frames)
        d["split"], d["x"] = it["split"], features(mel[:frames])
        items.append(d)
    cat = lambda key, split: np.concatenate([i[key] for i in items if i["split"] == split])
    v1 = np.concatenate([i["v1"] for i in items])
    terms = {k: np.concatenate([i["terms"][k] for i in items]) for k in ["dyn", "tempo", "dens"]}
    print("variance of the v1 terms (inside tanh):", {k: round(float(np.var(v)), 3) for k, v in terms.items()})
    for k, v in terms.items():
        print(f"r(v1 proxy, {k} term) = {np.corrcoef(v1, v)[0, 1]:.3f}")
    means = np.concatenate([np.full(len(i["v1"]), i["v1"].mean()) for i in items])
    print(f"share of the v1 proxy's variance between items: {np.var(means) / np.var(v1):.3f}")
    print(f"frames whose v1 dynamic is 0 only because a detache gap is sampled: "
          f"{100 * np.concatenate([i['gap'] for i in items]).mean():.1f} %")
    print(f"r(v1, v2) = {np.corrcoef(v1, np.concatenate([i['v2'] for i in items]))[0, 1]:.3f}")
    xtr, xva = cat("x", "train"), cat("x", "val")
    for key in ["v1", "tempo", "density", "mean_dyn", "v2"]:
        gbm = HistGradientBoostingRegressor(max_iter=300, learning_rate=0.05, random_state=0)
        gbm.fit(xtr, cat(key, "train"))
        r_tr = np.corrcoef(gbm.predict(xtr), cat(key, "train"))[0, 1]
        r_va = np.corrcoef(gbm.predict(xva), cat(key, "val"))[0, 1]
        print(f"gradient boosting on 2 fps mel features -> {key}: train r {r_tr:.3f}, validation r {r_va:.3f}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
