#!/usr/bin/env python3
"""How many of the decoder's beats fall after the music has ended, and what beat F would be
without them: the shipped choice of each item of a `beat_candidates` file, scored as
`evaluate` scores beats (beats before 5 s trimmed, ±70 ms, one match per labelled beat),
then again without the beats later than the last *labelled* note's end + 70 ms (an upper
bound on what trimming at the music's end can gain). Works of one split.

    cargo run --release -p violin-train --example beat_candidates -- CORPUS cands.jsonl
    python3 scripts/beats_after_end.py CORPUS cands.jsonl Val
"""
import json
import sys

import numpy as np

from corpus_items import column, f_measure, shipped_choice


def matched(ref, est):
    used, m = set(), 0
    for t in est:
        d = np.abs(ref - t)
        j = int(np.argmin(d))
        if d[j] <= 0.07 and j not in used:
            used.add(j)
            m += 1
    return m


def main():
    corpus, path, split = sys.argv[1], sys.argv[2], sys.argv[3]
    m = r = e = after = m2 = e2 = 0
    for line in open(path):
        it = json.loads(line)
        if it["etude"] or it["split"] != split:
            continue
        c = shipped_choice(it)
        ref = np.array(column(f"{corpus}/{it['item']}/beats.txt"))
        est = np.array(c["beats_s"])
        ref, est = ref[ref >= 5], est[est >= 5]
        if len(ref) == 0:
            continue
        notes = np.loadtxt(f"{corpus}/{it['item']}/notes.tsv", skiprows=1, usecols=(0, 1), ndmin=2)
        keep = est[est <= notes[:, 1].max() + 0.07]
        m, r, e = m + matched(ref, est), r + len(ref), e + len(est)
        after += int(np.sum(est > ref[-1] + 0.07))
        m2, e2 = m2 + matched(ref, keep), e2 + len(keep)
    print(f"{split} works: {e} beats, {after} after the last labelled beat; beat F "
          f"{f_measure(m, r, e):.3f}, without the beats after the last note's end {f_measure(m2, r, e2):.3f}")


if __name__ == "__main__":
    main()
