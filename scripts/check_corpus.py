#!/usr/bin/env python3
"""Summarise a many-violin corpus and check its labels: every bow change lies on a note onset,
every double stop sounds with a melody note (same onset and offset) one string lower.

    python3 scripts/check_corpus.py CORPUS_DIR
"""
import json, sys, collections, os
root = sys.argv[1]
m = json.load(open(f"{root}/manifest.json"))
items = m["items"]
bad = 0; changes = 0; seconds = 0; bad_seconds = 0
for it in items:
    d = f"{root}/{it['dir']}"
    melody = [l.split("\t") for l in open(f"{d}/notes.tsv").read().splitlines()[1:] if l]
    onsets = [float(n[0]) for n in melody]
    for l in (open(f"{d}/double_stops.tsv").read().splitlines()[1:] if os.path.exists(f"{d}/double_stops.tsv") else []):
        seconds += 1
        s = l.split("\t")
        if not any(n[0] == s[0] and n[1] == s[1] and int(n[3]) == int(s[3]) + 1 and int(n[2]) > int(s[2]) for n in melody):
            bad_seconds += 1
    for l in open(f"{d}/bowchanges.txt").read().split():
        changes += 1
        if not any(abs(float(l) - o) < 1e-5 for o in onsets):
            bad += 1
hours = sum(i["duration_s"] for i in items) / 3600
works = {i["work"] for i in items if not i["work"].startswith("etude/")}
print(f"items {len(items)}, hours {hours:.2f}, repertoire works {len(works)}, études {sum(i['work'].startswith('etude/') for i in items)}")
print("violins", dict(collections.Counter(i["violin"] for i in items)))
print("sets", dict(collections.Counter((i["split"], i["held_out"]) for i in items)))
print("meters", collections.Counter(i["meter"] for i in items).most_common())
recs = [i["recording"] for i in items if i.get("recording")]
print("rates", dict(collections.Counter(r["sample_rate_hz"] for r in recs)), "stereo", sum(r["channels"] == 2 for r in recs), "lossy", dict(collections.Counter((r["lossy"] or {}).get("kind", "none") for r in recs)))
rt = sorted(r["rt60_s"] for r in recs); print(f"rt60 min/median/max {rt[0]:.2f}/{rt[len(rt)//2]:.2f}/{rt[-1]:.2f}", "peak dBFS min/max", round(min(r['peak_dbfs'] for r in recs),1), round(max(r['peak_dbfs'] for r in recs),1))
print(f"bow changes {changes}, not on a note onset: {bad}")
print("skipped scores", len(m["skipped_scores"]), "double stops played", m.get("double_stops_played", 0), "chord pitches dropped", m.get("chord_pitches_dropped", 0))
print(f"double stops {seconds}, not under a melody note one string lower: {bad_seconds}")
tempi = sorted(i["tempo_bpm"] for i in items); print(f"tempo min/median/max {tempi[0]:.0f}/{tempi[len(tempi)//2]:.0f}/{tempi[-1]:.0f}")
