#!/usr/bin/env python3
"""Item by item, what a change did: two `evaluate --report` files of the same items (before,
after), and for each measure the pooled figure before and after, how many items got better
and how many worse, a two-sided sign test over those, and the items that moved most.
Standard library only.

    violin-skeleton evaluate --data CORPUS --split val --report before.json
    (change something, rebuild)
    violin-skeleton evaluate --data CORPUS --split val --report after.json
    python3 scripts/compare_reports.py before.json after.json [--top 3]

A mean over items can be moved by a few discrete flips (a stroke direction that turns and
takes the bow arm with it for seconds); counting items that got better and worse shows
whether a change helps most items or a few a lot. Event measures (bow changes, onsets, beats,
downbeats, bowing attacks) are F1 per item and pooled over items; tallies (stroke directions,
sounding strings) are shares; the motion distances are duration-weighted means, lower better.
"""
import json
import math
import sys

from corpus_items import f_measure

EVENTS = ["bow_changes_2f", "onsets", "beats", "downbeats", "bowing_attacks_3f"]
TALLIES = ["stroke_directions", "sounding_strings"]
FLAGS = ["meter_correct", "tempo_correct"]
DISTANCES = ["right_wrist_l1_px", "skeleton_l1_px", "jitter_px"]


def per_item(rec, key):
    v = rec.get(key)
    if v is None:
        return None
    if key in EVENTS:
        return f_measure(v["matched"], v["reference"], v["estimated"])
    if key in TALLIES:
        return v["right"] / v["total"] if v["total"] else None
    return float(v)


def pooled(recs, key):
    rows = [r for r in recs if r.get(key) is not None]
    if not rows:
        return float("nan")
    if key in EVENTS:
        return f_measure(*(sum(r[key][k] for r in rows) for k in ("matched", "reference", "estimated")))
    if key in TALLIES:
        return sum(r[key]["right"] for r in rows) / max(sum(r[key]["total"] for r in rows), 1)
    if key in FLAGS:
        return sum(bool(r[key]) for r in rows) / len(rows)
    w = sum(r["duration_s"] for r in rows)
    return sum(r[key] * r["duration_s"] for r in rows) / w


def sign_test(better, worse):
    """Two-sided p of at least this imbalance among better + worse fair coin flips."""
    n, k = better + worse, min(better, worse)
    if n == 0:
        return 1.0
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2 ** n
    return min(1.0, 2 * tail)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    top = int(sys.argv[sys.argv.index("--top") + 1]) if "--top" in sys.argv else 3
    if len(args) < 2:
        sys.exit(__doc__)
    before = {r["name"]: r for r in json.load(open(args[0]))["recordings"]}
    after = {r["name"]: r for r in json.load(open(args[1]))["recordings"]}
    names = sorted(set(before) & set(after))
    print(f"{len(names)} items in both reports")
    print("| measure | before | after | items better | worse | sign test p | most moved |")
    print("|---|---|---|---|---|---|---|")
    for key in EVENTS + TALLIES + FLAGS + DISTANCES:
        lower_better = key in DISTANCES
        moves = []
        for n in names:
            a, b = per_item(before[n], key), per_item(after[n], key)
            if a is None or b is None or abs(b - a) < 1e-9:
                continue
            moves.append((b - a, n))
        better = sum((d < 0) == lower_better for d, _ in moves)
        worse = len(moves) - better
        moves.sort(key=lambda m: -abs(m[0]))
        most = ", ".join(f"{n} {d:+.3g}" for d, n in moves[:top])
        b0 = pooled([before[n] for n in names], key)
        b1 = pooled([after[n] for n in names], key)
        print(f"| {key} | {b0:.3f} | {b1:.3f} | {better} | {worse} | "
              f"{sign_test(better, worse):.2f} | {most} |")


if __name__ == "__main__":
    main()
