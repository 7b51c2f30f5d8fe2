#!/usr/bin/env python3
"""Beat, downbeat, metre and tempo figures of an `evaluate` report broken down by the items'
notated time signature (études and works apart), with the notated tempo at which tempo
errors happen. Reads the corpus manifest for each item's metre, tempo and source.

    violin-skeleton evaluate --data CORPUS --split train --report train.json
    python3 scripts/beats_by_meter.py CORPUS train.json
"""
import collections
import json
import sys

corpus, report_path = sys.argv[1], sys.argv[2]
items = {it["dir"]: it for it in json.load(open(f"{corpus}/manifest.json"))["items"]}
report = json.load(open(report_path))

# sums: beats matched/reference/estimated, downbeats the same, metre, tempo, octave, items
sums = collections.defaultdict(lambda: [0] * 9)
slow = collections.defaultdict(lambda: [0, 0])  # tempo right, items; notated tempo < 70 bpm
for rec in report["recordings"]:
    it = items.get(rec["name"])
    if it is None:
        continue
    kind = "étude" if "etude" in it["source"] else "work"
    s = sums[(kind, it["meter"])]
    b, d = rec["beats"], rec["downbeats"]
    for k, v in enumerate((b["matched"], b["reference"], b["estimated"],
                           d["matched"], d["reference"], d["estimated"])):
        s[k] += v
    s[6] += rec["meter_correct"]
    s[7] += rec["tempo_correct"]
    s[8] += 1
    if it["tempo_bpm"] < 70:
        slow[(kind, it["meter"])][0] += rec["tempo_correct"]
        slow[(kind, it["meter"])][1] += 1


def f_measure(matched, reference, estimated):
    return 2 * matched / max(reference + estimated, 1)


print("| kind | metre | items | beat F | beats est/ref | downbeat F | downbeats est/ref "
      "| metre right | tempo right | tempo right, notated < 70 bpm |")
print("|---|---|---|---|---|---|---|---|---|---|")
for (kind, meter), s in sorted(sums.items()):
    if s[8] < 10:
        continue
    right, n = slow[(kind, meter)]
    slow_txt = f"{right / n:.2f} of {n}" if n else "–"
    print(f"| {kind} | {meter} | {s[8]} | {f_measure(*s[0:3]):.3f} | {s[2] / max(s[1], 1):.2f} "
          f"| {f_measure(*s[3:6]):.3f} | {s[5] / max(s[4], 1):.2f} | {s[6] / s[8]:.2f} "
          f"| {s[7] / s[8]:.2f} | {slow_txt} |")
