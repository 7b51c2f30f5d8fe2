#!/usr/bin/env python3
"""Where the learned fingering planner's hand sits against the violinists': position shares,
shifts per note and the positions it misses, from leave-one-piece-out plans of the ten
training pieces (the reserved pieces are never read).

    for p in beeth1 beeth2_1 beeth2_2 elgar mend2 mend3 mozart1 mozart2_1 mozart2_2 wind; do
      cargo run --release -p fingering --features train --example tnua -- DIR \\
        --fixed 20,200,2,2,0.5,0.5 --span 4,0,2,1 --debug $p > plans/$p.txt
    done
    python3 scripts/fingering_positions.py plans

Each `--debug` line: index, MIDI pitch, the plan's place (string 1–4 = G–E, position,
finger; then its placement), `XX` where no violinist agrees, and the ten violinists' places
(`-` where one gave none). Open strings (finger 0) are left out of the position figures.
"""
import collections
import glob
import os
import re
import sys


def place(token):
    """(string, position, finger) of a `--debug` place such as `331` or `3102`."""
    return int(token[0]), int(token[1:-1]), int(token[-1])


def read(folder):
    plans, players = {}, {}
    for path in sorted(glob.glob(os.path.join(folder, "*.txt"))):
        piece = os.path.basename(path)[:-4]
        plan, labels = [], []
        for line in open(path):
            t = line.split()
            if len(t) < 12:
                continue
            plan.append(place(re.match(r"\d+", t[2]).group()))  # digits, then the placement
            labels.append([None if x == "-" else place(x) for x in t[-10:]])
        plans[piece], players[piece] = plan, labels
    return plans, players


def shifts_and_shares(sequences):
    shifts = stopped = 0
    share = collections.Counter()
    for seq in sequences:
        last = None
        for p in seq:
            if p is None or p[2] == 0:
                continue
            stopped += 1
            share[p[1]] += 1
            shifts += last is not None and p[1] != last
            last = p[1]
    return shifts / max(stopped, 1), {k: v / max(stopped, 1) for k, v in sorted(share.items())}


def main():
    plans, players = read(sys.argv[1])
    each_player = [[row[v] for row in players[p]] for p in players for v in range(10)]
    for name, seqs in (("plan", list(plans.values())), ("violinists", each_player)):
        rate, share = shifts_and_shares(seqs)
        shares = " ".join(f"{k}:{v:.3f}" for k, v in share.items() if v >= 0.001)
        print(f"{name}: {rate:.3f} position changes per stopped note; positions {shares}")
    right = wrong_string = notes = 0
    misses = collections.Counter()
    for piece, plan in plans.items():
        for p, row in zip(plan, players[piece]):
            given = [x for x in row if x]
            if not given:
                continue
            notes += 1
            key = collections.Counter((x[0], x[1] if x[2] else "open") for x in given)
            top = key.most_common(1)[0][0]
            mine = (p[0], p[1] if p[2] else "open")
            if mine == top:
                right += 1
            elif mine[0] != top[0]:
                wrong_string += 1
            else:
                misses[(mine[1], top[1])] += 1
    print(f"against the most common place: {right} of {notes} right, {wrong_string} on another string")
    print("same string, other position (plan -> violinists), the most frequent:")
    for (mine, theirs), n in misses.most_common(6):
        print(f"  {mine} -> {theirs}: {n}")


if __name__ == "__main__":
    main()
