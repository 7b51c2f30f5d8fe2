#!/usr/bin/env python3
"""How far the analysis's note ends are from the labelled ones: every item of a corpus split
is analysed (`violin-skeleton analyze`), each labelled note is matched to the analysed note
whose onset is nearest (within 50 ms), and the offset errors (analysed − labelled) are
summarised for notes followed by a rest of at least 0.25 s or ending the item, and for the
others (legato). Standard library and numpy.

    python3 scripts/offset_errors.py CORPUS val [path/to/violin-skeleton]
"""
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

import numpy as np


def errors(binary, corpus, item, tmp):
    d = os.path.join(corpus, item["dir"])
    out = os.path.join(tmp, f"{item['id']}.json")
    subprocess.run([binary, "analyze", "-q", os.path.join(d, item["audio"]), "-o", out], check=True)
    notes = json.load(open(out))["notes"]
    analysed = np.array([[n["onset_s"], n["offset_s"]] for n in notes]).reshape(-1, 2)
    labelled = np.loadtxt(os.path.join(d, "notes.tsv"), skiprows=1, usecols=(0, 1), ndmin=2)
    rest, legato = [], []
    for k, (on, off) in enumerate(labelled):
        following = labelled[k + 1, 0] if k + 1 < len(labelled) else np.inf
        if len(analysed) == 0:
            continue
        j = int(np.argmin(np.abs(analysed[:, 0] - on)))
        if abs(analysed[j, 0] - on) <= 0.05:
            (rest if following - off >= 0.25 else legato).append(analysed[j, 1] - off)
    return rest, legato


def main():
    corpus, split = sys.argv[1], sys.argv[2]
    binary = sys.argv[3] if len(sys.argv) > 3 else "violin-skeleton"
    items = [it for it in json.load(open(os.path.join(corpus, "manifest.json")))["items"]
             if it["split"] == split]
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(2) as pool:
        res = list(pool.map(lambda it: errors(binary, corpus, it, tmp), items))
    for name, k in (("followed by a rest or last", 0), ("legato", 1)):
        e = np.array([x for r in res for x in r[k]])
        print(f"{name}: {len(e)} notes, median error {np.median(e):+.3f} s, median |error| "
              f"{np.median(np.abs(e)):.3f} s, 10th/90th percentile {np.percentile(e, 10):+.3f} / "
              f"{np.percentile(e, 90):+.3f} s, later than +0.15 s {np.mean(e > 0.15):.2f}")


if __name__ == "__main__":
    main()
