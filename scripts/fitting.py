"""Shared by scripts/fit_beat_level.py and scripts/fit_meter.py."""
import numpy as np


def five_fold_cv(data, fit, score, seed=1):
    """Mean over 5 folds (items permuted with `seed`) of `score(held_out, fit(rest))`."""
    order = np.random.default_rng(seed).permutation(len(data))
    folds = np.array_split(order, 5)
    scores = []
    for k in range(5):
        held = set(folds[k].tolist())
        model = fit([data[i] for i in order if i not in held])
        scores.append(score([data[i] for i in folds[k]], model))
    return float(np.mean(scores))
