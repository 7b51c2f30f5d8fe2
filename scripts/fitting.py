"""Shared by scripts/fit_beat_level.py and scripts/fit_meter.py."""
import json
import os
import pathlib
import subprocess
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
DUMP = ROOT / "target" / "release" / "examples" / "level_features"


def dump_level_features(corpus, splits, bow_dir=None):
    """The manifest items of `splits` and, for each, the `level_features` dump of its audio.

    `bow_dir` holds `violin-skeleton analyze` outputs named `<manifest index>.json`; their
    `bow_changes_s` reach the tracker as the facade passes them (`BOW_CHANGES_DIR`)."""
    manifest = json.loads((corpus / "manifest.json").read_text())
    chosen = [(i, it) for i, it in enumerate(manifest["items"]) if it["split"] in splits]
    items = [it for _, it in chosen]
    files = [str(corpus / it["dir"] / "audio.wav") for it in items]
    with tempfile.TemporaryDirectory() as out, tempfile.TemporaryDirectory() as bows:
        env = dict(os.environ)
        if bow_dir is not None:
            # level_features numbers its inputs 0, 1, …: link each item's analysis to its position.
            for pos, (index, _) in enumerate(chosen):
                os.symlink(bow_dir.resolve() / f"{index}.json", pathlib.Path(bows) / f"{pos}.json")
            env["BOW_CHANGES_DIR"] = bows
        subprocess.run([str(DUMP), out, *files], check=True, env=env)
        dumps = [json.loads((pathlib.Path(out) / f"{i}.json").read_text()) for i in range(len(files))]
    return items, dumps


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
