#!/usr/bin/env python3
"""Are the double stops of a MIDI analysis playable? Works of the repertoire export with at
least ten chords are written as MIDI files (format 0, the score's first time signature and
its marked tempo or 100 quarters per minute, every chord note kept), analysed by each
`violin-skeleton` binary given, and every two-note chord of the analysis is checked: its
notes on neighbouring strings, and in reach of one hand (one of them open, or positions at
most one apart).

    python3 scripts/export_repertoire.py data/repertoire        # once (crates/corpus/README.md)
    cargo build --release
    python3 scripts/double_stop_playability.py data/repertoire OUT target/release/violin-skeleton [OTHER_BINARY ...]

Prints, per binary, the two-note chords analysed and how many are not playable. Files the
CLI refuses (for instance longer than its 60-minute MIDI limit) are reported and skipped.
"""

import collections
import glob
import json
import os
import struct
import subprocess
import sys

DIVISION = 480
MIN_CHORDS = 10


def vlq(v):
    """A MIDI variable-length quantity."""
    out = [v & 0x7F]
    v >>= 7
    while v:
        out.insert(0, 0x80 | (v & 0x7F))
        v >>= 7
    return bytes(out)


def smf(events):
    """A format-0 file from (delta ticks, event bytes)."""
    track = b"".join(vlq(d) + bytes(b) for d, b in events) + bytes([0, 0xFF, 0x2F, 0])
    header = b"MThd" + struct.pack(">IHHH", 6, 0, 1, DIVISION)
    return header + b"MTrk" + struct.pack(">I", len(track)) + track


def midi_of(score):
    """The score's notes, chords kept, as MIDI bytes."""
    qpm = score.get("tempo_qpm") or 100.0
    mpq = int(60e6 / qpm)
    timed = []
    for n in score["notes"]:
        t0 = round(n["start_q"] * DIVISION)
        t1 = max(round((n["start_q"] + n["dur_q"]) * DIVISION) - 10, t0 + 1)
        for m in n["midi"]:
            timed += [(t0, 1, m), (t1, 0, m)]
    timed.sort()
    bar = score["bars"][0]
    den = {1: 0, 2: 1, 4: 2, 8: 3, 16: 4}.get(bar["denominator"], 2)
    events = [
        (0, [0xFF, 0x51, 3, (mpq >> 16) & 255, (mpq >> 8) & 255, mpq & 255]),
        (0, [0xFF, 0x58, 4, bar["numerator"], den, 24, 8]),
    ]
    last = 0
    for t, on, m in timed:
        events.append((t - last, [0x90 if on else 0x80, m, 80 if on else 0]))
        last = t
    return smf(events)


def check(path):
    """(two-note chords, unplayable ones) of an analysis file."""
    with open(path) as f:
        notes = json.load(f)["notes"]
    by_onset = collections.defaultdict(list)
    for n in notes:
        if n.get("string") is not None:
            by_onset[round(n["onset_s"], 3)].append(n)
    chords = bad = 0
    for pair in by_onset.values():
        if len(pair) != 2:
            continue
        chords += 1
        a, b = pair
        neighbours = abs(a["string"] - b["string"]) == 1
        reach = (
            a["finger"] == 0
            or b["finger"] == 0
            or abs(a["position"] - b["position"]) <= 1
        )
        bad += not (neighbours and reach)
    return chords, bad


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    repertoire, out_dir, binaries = sys.argv[1], sys.argv[2], sys.argv[3:]
    os.makedirs(out_dir, exist_ok=True)
    files = []
    for path in sorted(glob.glob(os.path.join(repertoire, "*.json"))):
        with open(path) as f:
            score = json.load(f)
        if sum(len(n["midi"]) > 1 for n in score["notes"]) >= MIN_CHORDS:
            name = os.path.join(out_dir, os.path.basename(path)[:-5])
            with open(name + ".mid", "wb") as f:
                f.write(midi_of(score))
            files.append(name)
    print(f"{len(files)} works with at least {MIN_CHORDS} chords")
    for k, exe in enumerate(binaries):
        chords = bad = 0
        for name in files:
            out = f"{name}.{k}.json"
            run = subprocess.run(
                [exe, "analyze", "-q", name + ".mid", "-o", out],
                capture_output=True,
                text=True,
            )
            if run.returncode:
                print(f"  skipped: {run.stderr.strip()}")
                continue
            c, b = check(out)
            chords, bad = chords + c, bad + b
        print(
            f"{exe}: {chords} two-note chords, {bad} not playable ({bad / max(chords, 1):.3f})"
        )


if __name__ == "__main__":
    main()
