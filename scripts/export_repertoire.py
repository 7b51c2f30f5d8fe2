#!/usr/bin/env python3
"""Export public-domain violin repertoire from music21's corpus as violin-skeleton score JSON.

The corpus builder (`violin-skeleton corpus --repertoire DIR`) reads the files this script
writes: one JSON file per work part, with the score structure the labels need (bars and their
time signatures, pickups, slurs, staccato/accents, fermatas, dynamics, marked tempo).

    pip install music21
    python3 scripts/export_repertoire.py --out data/repertoire [--per-collection 400] [--seed 1]

What it reads (all shipped inside the `music21` package, see DATA_SOURCES.md for licences):
  * fiddle tunes: O'Neill's Music of Ireland (oneills1850), Ryan's Mammoth Collection
    (ryansMammoth), Aird's Airs (airdsAirs), the Nottingham folk-tune database
    (nottingham-dataset); folk songs: Essen (essenFolksong);
  * string parts: the violin I and violin II parts of the string quartets of Haydn, Mozart and
    Beethoven in the corpus, and both violin parts of Corelli's trio sonatas op. 3.

Reserved works are never exported (the product is evaluated on them elsewhere):
mozart/k458, haydn/opus74no1, beethoven/opus18no1, anything by J. S. Bach (this covers
BWV 1001-1006), and anything whose path or title names Wohlfahrt or Kayser. The skip list is
written to `DIR/skipped.tsv` with the reason, like every score that fails to parse.

Of each tune collection, --per-collection tunes are drawn at random, plus every tune in a
rare meter (12/8, 9/8, 3/8, read from the ABC `M:` field).

Tunes are moved up by octaves until their lowest note is at least G3 (MIDI 55); a work whose
range then exceeds E7 (MIDI 100) is skipped. Chords keep every pitch (`midi` is a list);
ties are merged. Everything is deterministic for a given --seed (which tunes are picked).
"""

import argparse
import json
import random
import re
import sys
import traceback
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

SCHEMA = "violin-skeleton-score/1"
RESERVED = [
    r"mozart/k458",
    r"haydn/opus74no1",
    r"beethoven/opus18no1",
    r"(^|/)bach/",
    r"bwv\s*100[1-6]",
    r"wohlfahrt",
    r"kayser",
]
TUNE_COLLECTIONS = {
    "oneills1850": "O'Neill, Music of Ireland (1903); ABC transcription in the music21 corpus",
    "ryansMammoth": "Ryan's Mammoth Collection (1883); ABC transcription in the music21 corpus",
    "airdsAirs": "Aird, A Selection of Scotch, English, Irish and Foreign Airs (1782-1803); ABC in the music21 corpus",
    "nottingham-dataset": "Nottingham folk music database (ABC), in the music21 corpus",
    "essenFolksong": "Essen Folksong Collection (ABC), in the music21 corpus",
}
QUARTETS = [
    "haydn/opus1no1",
    "mozart/k80",
    "mozart/k155",
    "mozart/k156",
    "beethoven/opus18no3.mxl",
    "beethoven/opus18no4.mxl",
    "beethoven/opus18no5.mxl",
    "beethoven/opus59no1",
    "beethoven/opus59no2",
    "beethoven/opus59no3",
    "beethoven/opus74.mxl",
    "beethoven/opus132.mxl",
    "beethoven/opus133.mxl",
    "corelli/opus3no1",
]
# Compound and one-beat meters are rare in the collections; every tune in one of them is
# exported on top of the random sample, so that the corpus has enough of each.
RARE_METERS = {"12/8", "9/8", "3/8"}
LICENCE_TUNES = "public-domain tune; encoding distributed in the music21 corpus (see music21/corpus/license.txt)"
LICENCE_PARTS = "public-domain composition; MusicXML encoding distributed in the music21 corpus (see music21/corpus/license.txt)"
DYNAMICS = {
    "pppp": 0.05, "ppp": 0.12, "pp": 0.22, "p": 0.35, "mp": 0.48, "mf": 0.6,
    "f": 0.75, "ff": 0.88, "fff": 0.96, "ffff": 1.0, "fp": 0.75, "sf": 0.8,
    "sfz": 0.85, "sffz": 0.9, "fz": 0.8, "rfz": 0.8, "sfp": 0.8,
}
ACCENTED_DYNAMICS = {"sf", "sfz", "sffz", "fz", "rfz", "fp", "sfp"}


def reserved(text):
    t = text.lower()
    return any(re.search(p, t) for p in RESERVED)


def corpus_root():
    import music21

    return Path(music21.__file__).parent / "corpus"


def part_to_score(part, meta):
    """One music21 Part -> the score dict, or raises ValueError with a reason."""
    from music21 import note, chord, dynamics, expressions, articulations, spanner

    measures = list(part.getElementsByClass("Measure"))
    if not measures:
        raise ValueError("no measures")
    # Slur ranges from the part as written (before ties are merged).
    flat = part.flatten()
    slur_ranges = []
    for sl in part.spannerBundle.getByClass("Slur"):
        els = [e for e in sl.getSpannedElements() if hasattr(e, "pitches")]
        if len(els) < 2:
            continue
        try:
            offs = [float(e.getOffsetInHierarchy(part)) for e in els]
        except Exception:
            continue
        slur_ranges.append((min(offs), max(offs)))
    dyn_marks = []
    for d in flat.getElementsByClass(dynamics.Dynamic):
        v = DYNAMICS.get(str(d.value).lower())
        if v is not None:
            dyn_marks.append((float(d.getOffsetInHierarchy(part)), v, str(d.value).lower()))
    dyn_marks.sort()

    bars = []
    ts = None
    for m in measures:
        if m.timeSignature is not None:
            ts = m.timeSignature
        if ts is None:
            ts = m.getContextByClass("TimeSignature")
        if ts is None:
            raise ValueError("no time signature")
        bars.append({
            "start_q": round(float(m.getOffsetInHierarchy(part)), 6),
            "len_q": round(float(m.duration.quarterLength), 6),
            "numerator": int(ts.numerator),
            "denominator": int(ts.denominator),
        })
    tempo = None
    for mm in flat.getElementsByClass("MetronomeMark"):
        if mm.number is not None:
            tempo = float(mm.getQuarterBPM() or mm.number)
            break

    stripped = part.stripTies(inPlace=False).flatten()
    notes = []
    for n in stripped.notes:
        if isinstance(n, chord.Chord):
            midis = sorted({int(p.midi) for p in n.pitches})
        elif isinstance(n, note.Note):
            midis = [int(n.pitch.midi)]
        else:
            continue
        dur = float(n.duration.quarterLength)
        if dur <= 0:  # grace notes
            continue
        start = float(n.getOffsetInHierarchy(stripped))
        arts = {type(a).__name__ for a in n.articulations}
        exprs = {type(e).__name__ for e in n.expressions}
        notes.append({
            "start_q": round(start, 6),
            "dur_q": round(dur, 6),
            "midi": midis,
            "staccato": bool(arts & {"Staccato", "Staccatissimo", "Spiccato"}),
            "accent": bool(arts & {"Accent", "StrongAccent"}),
            "fermata": "Fermata" in exprs,
        })
    if len(notes) < 8:
        raise ValueError(f"only {len(notes)} notes")
    notes.sort(key=lambda n: n["start_q"])
    # Slurred: a note strictly inside or at the end of a slur continues the previous stroke.
    for n in notes:
        s = n["start_q"]
        n["slurred"] = any(a < s - 1e-6 and s <= b + 1e-6 for a, b in slur_ranges)
    # Dynamics: the latest mark at or before the note; sf-type marks accent the note.
    k = 0
    level = None
    for n in notes:
        while k < len(dyn_marks) and dyn_marks[k][0] <= n["start_q"] + 1e-6:
            level = dyn_marks[k][1]
            if dyn_marks[k][2] in ACCENTED_DYNAMICS and abs(dyn_marks[k][0] - n["start_q"]) < 1e-6:
                n["accent"] = True
            k += 1
        n["dynamic"] = level
    lo = min(min(n["midi"]) for n in notes)
    shift = 0
    while lo + shift < 55:
        shift += 12
    hi = max(max(n["midi"]) for n in notes) + shift
    if hi > 100:
        raise ValueError(f"range {lo}..{hi - shift} does not fit G3..E7 after octave shifts")
    for n in notes:
        n["midi"] = [m + shift for m in n["midi"]]
    out = dict(meta)
    out.update({
        "schema": SCHEMA,
        "transposed_semitones": shift,
        "tempo_qpm": tempo,
        "bars": bars,
        "notes": notes,
    })
    return out


def export_file(job):
    """Parses one corpus file; returns (written, skipped) lists."""
    rel, kind, picks, out_dir = job
    from music21 import converter, stream

    path = corpus_root() / rel
    written, skipped = [], []
    if kind == "tunes":
        coll = rel.split("/")[0]
        for idx, text in enumerate(abc_tunes(path)):
            if picks is not None and idx not in picks:
                continue
            try:
                sc = converter.parse(text, format="abc")
            except Exception as e:
                skipped.append((f"{coll}/{Path(rel).stem}/{idx:04d}",
                                f"parse failed: {type(e).__name__}: {e}".replace("\n", " ")[:200]))
                continue
            title = (sc.metadata.title if sc.metadata and sc.metadata.title else "") or f"tune {idx}"
            num = getattr(sc.metadata, "number", None) if sc.metadata else None
            stem = Path(rel).stem
            wid = f"{coll}/{stem}/{idx:04d}"
            if reserved(wid) or reserved(title):
                skipped.append((wid, "reserved"))
                continue
            parts = list(sc.parts) or [sc]
            try:
                d = part_to_score(parts[0], {
                    "id": wid, "work": wid, "collection": coll, "title": title,
                    "number": str(num) if num else None,
                    "source": f"music21 corpus: {rel} (tune {idx})",
                    "origin": TUNE_COLLECTIONS.get(coll, coll), "license": LICENCE_TUNES,
                    "part": "melody",
                })
            except Exception as e:
                skipped.append((wid, f"{type(e).__name__}: {e}".replace("\n", " ")[:200]))
                continue
            write(out_dir, d)
            written.append(wid)
    else:
        try:
            parsed = converter.parse(str(path), forceSource=True)
        except Exception as e:
            return [], [(rel, f"parse failed: {type(e).__name__}: {e}".replace("\n", " ")[:200])]
        work = rel.rsplit("/", 1)[0] if rel.count("/") >= 2 else rel.replace(".mxl", "")
        coll = rel.split("/")[0]
        parts = list(parsed.parts)
        names = ["violin1", "violin2"]
        for pi, pname in enumerate(names[: min(2, len(parts))]):
            wid = f"{rel.replace('.mxl', '')}/{pname}"
            try:
                d = part_to_score(parts[pi], {
                    "id": wid, "work": work, "collection": coll,
                    "title": (parsed.metadata.title if parsed.metadata else None) or rel,
                    "number": None, "source": f"music21 corpus: {rel} (part {pi + 1})",
                    "origin": f"{coll} string parts in the music21 corpus", "license": LICENCE_PARTS,
                    "part": pname,
                })
            except Exception as e:
                skipped.append((wid, f"{type(e).__name__}: {e}".replace("\n", " ")[:200]))
                continue
            write(out_dir, d)
            written.append(wid)
    return written, skipped


def write(out_dir, d):
    p = Path(out_dir) / (d["id"].replace("/", "__") + ".json")
    tmp = p.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(d, separators=(",", ":")))
    tmp.replace(p)


def abc_tunes(path):
    """The tunes of an ABC file: each block from an `X:` line to the next, with the file
    header (lines before the first `X:`) prepended."""
    text = Path(path).read_text(encoding="latin-1")
    blocks = re.split(r"(?m)^(?=X:)", text)
    header, tunes = "", []
    for b in blocks:
        if b.startswith("X:"):
            tunes.append(b)
        elif not tunes:
            header = b
    return [header + t for t in tunes]


def tune_meters(rel):
    """The notated meter (`M:` field, spaces removed) of every tune of one ABC file."""
    meters = []
    for text in abc_tunes(corpus_root() / rel):
        m = re.search(r"(?m)^M:\s*([^\s%]+)", text.split("\nK:", 1)[0])
        meters.append(m.group(1).replace(" ", "") if m else "")
    return rel, meters


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, type=Path)
    ap.add_argument("--per-collection", type=int, default=400,
                    help="tunes picked per tune collection (seeded); 0 = all")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default=None, help="comma list of collections (for a quick sample)")
    args = ap.parse_args()
    root = corpus_root()
    args.out.mkdir(parents=True, exist_ok=True)
    only = set(args.only.split(",")) if args.only else None
    jobs, skipped = [], []
    rng = random.Random(args.seed)
    tune_files = {}
    for coll in TUNE_COLLECTIONS:
        if only and coll not in only:
            continue
        files = sorted(str(p.relative_to(root)) for p in (root / coll).rglob("*.abc"))
        tune_files[coll] = files
    with ProcessPoolExecutor(args.jobs) as ex:
        meters = dict(ex.map(tune_meters, [f for fs in tune_files.values() for f in fs]))
    for coll, files in tune_files.items():
        pool = [(f, i) for f in files for i in range(len(meters.get(f, [])))]
        if args.per_collection and len(pool) > args.per_collection:
            rare = [(f, i) for f, i in pool if meters[f][i] in RARE_METERS]
            pool = sorted(set(rng.sample(pool, args.per_collection)) | set(rare))
        by_file = {}
        for f, i in pool:
            by_file.setdefault(f, set()).add(i)
        for f, picks in sorted(by_file.items()):
            jobs.append((f, "tunes", picks, str(args.out)))
    for q in QUARTETS:
        if only and q.split("/")[0] not in only:
            continue
        if reserved(q):
            skipped.append((q, "reserved"))
            continue
        p = root / q
        files = [q] if p.is_file() else sorted(str(x.relative_to(root)) for x in p.glob("*.mxl"))
        for f in files:
            jobs.append((f, "parts", None, str(args.out)))
    written = []
    with ProcessPoolExecutor(args.jobs) as ex:
        for w, s in ex.map(export_file, jobs):
            written += w
            skipped += s
    with open(args.out / "skipped.tsv", "w") as fh:
        fh.write("work\treason\n")
        for w, r in sorted(skipped):
            fh.write(f"{w}\t{r}\n")
    print(f"{len(written)} scores written to {args.out}, {len(skipped)} skipped (skipped.tsv)")


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        sys.exit(130)
    except Exception:
        traceback.print_exc()
        sys.exit(1)
