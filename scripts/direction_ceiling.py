#!/usr/bin/env python3
"""How far stroke directions can be got right from the bow changes and the bars, and which of
the two costs more: the labelled strokes (`strokes.tsv`) and downbeats (`downbeats.txt`) of a
corpus, per evaluation set (training items skipped). Figures per set:

* rules: the first stroke down, a stroke within 0.1 s of a downbeat down, every other stroke
  the reverse of the previous *guess* (errors carry on to the next downbeat);
* one step: the same, but each guess reverses the previous *labelled* direction;
* decoder: a two-state (down, up) Viterbi over the strokes, as `stroke::direction` decodes
  them without the network: the direction flips at each change except with probability
  `stay`, and a stroke starting within 0.1 s of a downbeat gets a bonus `bonus` for a
  down-bow. `(bonus, stay)` is chosen on the validation split only (grid below) and then
  scored on every set.

With ANALYSES (folders of `analysis.json` files named by item, `00003.json`, as written by
`violin-skeleton analyze` for the items' audio), the decoder is also run on the analysis's
bow changes and/or downbeats in place of the labelled ones (each combination with its own
`(bonus, stay)` chosen on validation), and the analysis's own directions are scored.
Accuracy is counted per labelled stroke as `violin-skeleton evaluate` counts it: the stroke
sounding at the labelled stroke's midpoint must have its direction.

    python3 scripts/direction_ceiling.py CORPUS_DIR [ANALYSES_DIR ...]
"""
import bisect
import collections
import json
import math
import os
import sys

ON_DOWNBEAT_S = 0.1
BONUSES = [0.5, 1.0, 2.0, 3.0, 5.0]
STAYS = [0.01, 0.02, 0.05, 0.1, 0.2]


def read_lines(path):
    with open(path) as f:
        return f.read().splitlines()


def labelled(root, item):
    d = f"{root}/{item['dir']}"
    rows = [l.split("\t") for l in read_lines(f"{d}/strokes.tsv")[1:] if l.strip()]
    strokes = [(float(r[0]), float(r[1]), r[2].strip()) for r in rows]
    downbeats = [float(l.split()[0]) for l in read_lines(f"{d}/downbeats.txt") if l.strip()]
    return strokes, downbeats


def near(times, t, tol=ON_DOWNBEAT_S):
    i = bisect.bisect_left(times, t - tol)
    return i < len(times) and abs(times[i] - t) <= tol


def rules(strokes, downbeats, one_step):
    guess, right = None, 0
    for i, (start, _, direction) in enumerate(strokes):
        flip = lambda x: "up" if x == "down" else "down"
        if i == 0 or near(downbeats, start):
            guess = "down"
        else:
            guess = flip(strokes[i - 1][2] if one_step else guess)
        right += guess == direction
    return right


def viterbi(starts, downbeats, bonus, stay):
    """Directions (True = down) of strokes starting at `starts`."""
    if not starts:
        return []
    keep, flip = math.log(stay), math.log(1.0 - stay)
    emit = [bonus if near(downbeats, t) else 0.0 for t in starts]
    score = [emit[0], 0.0]  # down, up; ties go to down
    back = []
    for k in range(1, len(starts)):
        nxt, frm = [0.0, 0.0], [0, 0]
        for q in (0, 1):
            same, other = score[q] + keep, score[1 - q] + flip
            nxt[q], frm[q] = (same, q) if same >= other else (other, 1 - q)
        nxt[0] += emit[k]
        back.append(frm)
        score = nxt
    q = 0 if score[0] >= score[1] else 1
    out = [q]
    for frm in reversed(back):
        q = frm[q]
        out.append(q)
    return [q == 0 for q in reversed(out)]


def tally(truth, starts, downs):
    """Labelled strokes whose direction the stroke sounding at their midpoint has."""
    right = 0
    for s0, e0, direction in truth:
        if not starts:
            continue
        i = max(bisect.bisect_right(starts, (s0 + e0) / 2) - 1, 0)
        right += downs[i] == (direction == "down")
    return right


def main():
    root = sys.argv[1]
    analysis_dirs = sys.argv[2:]
    with open(f"{root}/manifest.json") as f:
        items = [it for it in json.load(f)["items"] if it["split"] != "train"]
    cases = collections.defaultdict(list)
    for it in items:
        strokes, downbeats = labelled(root, it)
        name = "validation" if it["split"] == "val" else it["held_out"]
        analysis = None
        base = os.path.basename(it["dir"]) + ".json"
        for d in analysis_dirs:
            if os.path.exists(os.path.join(d, base)):
                with open(os.path.join(d, base)) as f:
                    analysis = json.load(f)
                break
        cases[name].append((strokes, downbeats, analysis))

    sources = [("labelled", "labelled")]
    if analysis_dirs:
        sources += [("labelled", "analysis"), ("analysis", "labelled"), ("analysis", "analysis")]

    def score(name, source, bonus, stay):
        """Accuracy, or None when no item of the set has an analysis."""
        right = n = 0
        for strokes, downbeats, analysis in cases[name]:
            if source != ("labelled", "labelled") and analysis is None:
                continue
            starts = (
                [s[0] for s in strokes]
                if source[0] == "labelled"
                else [s["start_s"] for s in analysis["bow_strokes"]]
            )
            bars = downbeats if source[1] == "labelled" else analysis["downbeats_s"]
            right += tally(strokes, starts, viterbi(starts, bars, bonus, stay))
            n += len(strokes)
        return right / n if n else None

    chosen = {}
    for source in sources:
        grid = [(score("validation", source, b, s), b, s) for b in BONUSES for s in STAYS]
        best = max(grid, key=lambda g: g[0] or 0.0)  # first best in grid order
        chosen[source] = best[1:]
        print(f"decoder on {source[0]} strokes + {source[1]} downbeats: bonus {best[1]}, "
              f"stay {best[2]} (chosen on validation)")

    header = ["set", "strokes", "rules", "one step"]
    header += [f"decoder {a[:3]}.strokes {b[:3]}.downbeats" for a, b in sources]
    if analysis_dirs:
        header.append("analysis")
    print("\t".join(header))
    for name in sorted(cases):
        n = sum(len(c[0]) for c in cases[name])
        row = [name, str(n)]
        row.append(f"{sum(rules(s, d, False) for s, d, _ in cases[name]) / max(n, 1):.3f}")
        row.append(f"{sum(rules(s, d, True) for s, d, _ in cases[name]) / max(n, 1):.3f}")
        for source in sources:
            acc = score(name, source, *chosen[source])
            row.append("-" if acc is None else f"{acc:.3f}")
        if analysis_dirs:
            right = m = 0
            for strokes, _, analysis in cases[name]:
                if analysis is None:
                    continue
                starts = [s["start_s"] for s in analysis["bow_strokes"]]
                downs = [s["direction"] == "down" for s in analysis["bow_strokes"]]
                right += tally(strokes, starts, downs)
                m += len(strokes)
            row.append(f"{right / m:.3f}" if m else "-")
        print("\t".join(row))


if __name__ == "__main__":
    main()
