#!/usr/bin/env python3
"""How far the bowing rules alone can get stroke directions right when detection is perfect:
the labelled strokes (`strokes.tsv`) and downbeats (`downbeats.txt`) of a corpus, per
evaluation set (training items skipped). Two figures per set:

* rules on the true strokes and downbeats: the first stroke down, a stroke within 0.1 s of a
  downbeat down, every other stroke the reverse of the previous *guess* (errors carry on to
  the next downbeat, as in the analysis);
* one step: the same, but each guess reverses the previous *labelled* direction.

    python3 scripts/direction_ceiling.py CORPUS_DIR
"""
import collections
import json
import sys

root = sys.argv[1]
items = json.load(open(f"{root}/manifest.json"))["items"]
sums = collections.defaultdict(lambda: [0, 0, 0])
for it in items:
    if it["split"] == "train":
        continue
    d = f"{root}/{it['dir']}"
    lines = open(f"{d}/strokes.tsv").read().splitlines()[1:]
    strokes = [(float(l.split("\t")[0]), l.split("\t")[2].strip()) for l in lines if l.strip()]
    downbeats = [float(l.split()[0]) for l in open(f"{d}/downbeats.txt") if l.strip()]
    guess, chained, one_step = None, 0, 0
    for i, (start, direction) in enumerate(strokes):
        anchored = i == 0 or any(abs(start - t) <= 0.1 for t in downbeats)
        flip = lambda x: "up" if x == "down" else "down"
        guess = "down" if anchored else flip(guess)
        chained += guess == direction
        one_step += ("down" if anchored else flip(strokes[i - 1][1])) == direction
    name = "validation" if it["split"] == "val" else it["held_out"]
    s = sums[name]
    s[0] += chained
    s[1] += one_step
    s[2] += len(strokes)
print("set\tstrokes\trules on true strokes and downbeats\tone step")
for name, (chained, one_step, n) in sorted(sums.items()):
    print(f"{name}\t{n}\t{chained / max(n, 1):.3f}\t{one_step / max(n, 1):.3f}")
