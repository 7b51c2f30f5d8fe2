#!/usr/bin/env python3
"""Where downbeats go wrong: the recordings of `evaluate` reports sorted by whether the bar
length was right, whether the tempo was right (or at double/half), and whether the beats were
(beat F >= 0.8), each class with its count and its pooled downbeat F. Standard library only.

    violin-skeleton evaluate --data CORPUS --split val --report val.json
    python3 scripts/downbeat_errors.py val.json [more.json ...] [--group "val works"]

If downbeats are good wherever bar length, tempo and beats are right, the downbeat losses
come from the bar length and the tempo level, not from where bars start.
"""
import collections
import json
import sys


def f_measure(matched, reference, estimated):
    p = matched / max(estimated, 1)
    r = matched / max(reference, 1)
    return 2 * p * r / (p + r) if p + r > 0 else 0.0


def main(argv):
    group = None
    if "--group" in argv:
        i = argv.index("--group")
        group = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    if not argv:
        sys.exit(__doc__)
    # class -> [items, downbeats matched, reference, estimated]
    classes = collections.defaultdict(lambda: [0, 0, 0, 0])
    for path in argv:
        for rec in json.load(open(path))["recordings"]:
            if group is not None and rec.get("group") != group:
                continue
            b, d = rec["beats"], rec["downbeats"]
            if rec["tempo_correct"]:
                tempo = "tempo right"
            elif rec.get("tempo_octave_error"):
                tempo = "tempo x2 or x1/2"
            else:
                tempo = "tempo wrong"
            key = (
                "bar length right" if rec["meter_correct"] else "bar length wrong",
                tempo,
                "beat F >= 0.8" if f_measure(**b) >= 0.8 else "beat F < 0.8",
            )
            c = classes[key]
            c[0] += 1
            c[1] += d["matched"]
            c[2] += d["reference"]
            c[3] += d["estimated"]
    total = sum(c[0] for c in classes.values())
    print(f"{total} recordings")
    print("| bar length | tempo | beats | items | downbeat F |")
    print("|---|---|---|---|---|")
    for key, c in sorted(classes.items(), key=lambda kv: -kv[1][0]):
        print(f"| {key[0]} | {key[1]} | {key[2]} | {c[0]} | {f_measure(*c[1:]):.3f} |")


if __name__ == "__main__":
    main(sys.argv[1:])
