#!/usr/bin/env python3
"""Could the bow-stroke alternation choose where bars start? Validation split only.

Players hook strokes so that bars start down-bow (`performance::hooks_for_downbeats`), so
within a run of strokes between rests the downbeats should fall on strokes of one parity.
For each validation item this keeps the decoded beats and bar length of a
`violin-skeleton analyze` output and scores every bar phase (which beat of the bar is the
first) three ways, pooled over items (downbeat F ±70 ms):

* the decoded phase (what the analysis reports);
* the best phase against the labels (an upper bound for any phase choice);
* the phase whose downbeats agree most in stroke parity (detected bow changes, counted from
  the last rest of at least 0.15 s; ties to the decoded phase).

    for each val item: violin-skeleton analyze ITEM/audio.* -o OUT/NAME.json
    python3 scripts/bar_phase_parity.py CORPUS_DIR OUT
"""
import json
import sys

TOL_S = 0.07
REST_S = 0.15


def matched(est, ref):
    used, m = set(), 0
    for r in ref:
        best = None
        for i, e in enumerate(est):
            if i not in used and abs(e - r) <= TOL_S and (best is None or abs(e - r) < abs(est[best] - r)):
                best = i
        if best is not None:
            used.add(best)
            m += 1
    return m


def parities(changes, notes):
    """(run, parity) of each bow change: runs restart after a rest of REST_S."""
    notes = sorted(notes, key=lambda n: n["onset_s"])
    rests = [(a["offset_s"], b["onset_s"]) for a, b in zip(notes, notes[1:]) if b["onset_s"] - a["offset_s"] > REST_S]
    out, run, k = [], 0, 0
    for i, t in enumerate(changes):
        if i > 0 and any(changes[i - 1] < end <= t + 0.03 for _, end in rests):
            run, k = run + 1, 0
        out.append((run, k % 2))
        k += 1
    return out


def parity_score(downbeats, changes, par):
    counts = {}
    for t in downbeats:
        if not changes:
            break
        j = min(range(len(changes)), key=lambda j: abs(changes[j] - t))
        if abs(changes[j] - t) <= TOL_S:
            counts.setdefault(par[j][0], [0, 0])[par[j][1]] += 1
    return sum(max(v) - min(v) for v in counts.values())


def main():
    root, out = sys.argv[1], sys.argv[2]
    items = json.load(open(f"{root}/manifest.json"))["items"]
    totals = {"decoded": [0, 0, 0], "best against labels": [0, 0, 0], "stroke parity": [0, 0, 0]}
    for it in items:
        if it["split"] != "val":
            continue
        name = it["dir"].split("/")[-1]
        a = json.load(open(f"{out}/{name}.json"))
        beats, decoded = a["beats_s"], a["downbeats_s"]
        bar = (a.get("meter") or {}).get("beats_per_bar", 0)
        ref = [float(x) for x in open(f"{root}/{it['dir']}/downbeats.txt").read().split()]
        if not beats or not bar:
            continue
        first = min(range(len(beats)), key=lambda i: abs(beats[i] - decoded[0])) % bar if decoded else 0
        changes = a["bow_changes_s"]
        par = parities(changes, a["notes"])
        phases = []
        for ph in range(bar):
            d = [b for i, b in enumerate(beats) if i % bar == ph]
            m = matched(d, ref)
            f = 2 * m / (len(d) + len(ref)) if d or ref else 1.0
            phases.append((ph, parity_score(d, changes, par), f, m, len(d)))
        chosen = {
            "decoded": next(p for p in phases if p[0] == first),
            "best against labels": max(phases, key=lambda p: p[2]),
            "stroke parity": max(phases, key=lambda p: (p[1], p[0] == first)),
        }
        for key, p in chosen.items():
            t = totals[key]
            t[0] += p[3]
            t[1] += len(ref)
            t[2] += p[4]
    for key, (m, nref, nest) in totals.items():
        print(f"{key}: pooled downbeat F {2 * m / (nref + nest):.3f}")


if __name__ == "__main__":
    main()
