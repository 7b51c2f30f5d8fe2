#!/usr/bin/env python3
"""Would a perfect transcription tell the notated level? (beat-net EXPERIMENTS, rule R82.)

    pip install numpy scikit-learn
    python3 scripts/symbolic_metre_ceiling.py data/repertoire     # about 2 min on 2 cores

Excerpts of the repertoire's scores (the JSON files of `scripts/export_repertoire.py`) are
"performed" as the corpus does it (`corpus::perform`, `corpus::schedule`): time signatures
drawn with weight sqrt(count) and a work of it uniformly, 4-48 bars lasting about 8-40 s at
the marked tempo (or 100 bpm), the tempo marked +-15 % or drawn log-uniformly from 40-200
notated beats per minute, capped at 13 of the score's short notes per second. There is no
rubato and no onset noise: the classifier sees each note's exact onset, length and pitch.
From notation-free features of those notes (note rate, inter-onset intervals in seconds and
as multiples of the modal interval, onset autocorrelation at multiples of it, long notes,
intervals, range, pitch repetition) a gradient-boosted classifier (scikit-learn) learns the
beats per bar (what `evaluate` scores as metre) and the beat period as a multiple of the
modal interval in half-octave steps (tempo within 8 % when the multiple is right). It may
learn any style cue the scores carry, such as the Essen collection's songs in 3/8.

Works go to splits as in `corpus::schedule::work_split` (FNV-1a of the name, mod 10): train
works are fitted, validation works scored. A test work's file is parsed for its name and then
dropped, so nothing of it reaches a feature; the reserved works are not in the export. Seeds
are fixed, so a run repeats.
"""

import json, glob, math, random, collections, sys
import numpy as np
from sklearn.ensemble import HistGradientBoostingClassifier


def fnv(s):
    """FNV-1a (64-bit), as `corpus::schedule::work_hash`."""
    h = 0xCBF29CE484222325
    for b in s.encode():
        h ^= b
        h = (h * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def ts_of(d):
    """The main time signature, as `Score::main_time_signature`: the first full bar's."""
    for b in d["bars"]:
        if b["len_q"] >= b["numerator"] * 4.0 / b["denominator"] - 1e-6:
            return b["numerator"], b["denominator"]
    return d["bars"][0]["numerator"], d["bars"][0]["denominator"]


def meter(num, den):
    """(beats per bar, beat length in quarters), as `TimeSignature::meter` and `beat_quarters`."""
    dotted = den >= 8 and num % 3 == 0
    unit = 4.0 / den
    if dotted:
        return max(num // 3, 1), 3 * unit
    return max(num, 1), unit


scores = {"train": [], "val": []}
if len(sys.argv) != 2:
    sys.exit("usage: symbolic_metre_ceiling.py REPERTOIRE_DIR")
for f in sorted(glob.glob(sys.argv[1] + "/*.json")):
    d = json.load(open(f))
    sp = fnv(d["work"]) % 10
    if sp == 0:
        continue  # a test work: dropped once its name is hashed
    if not d["notes"] or not d["bars"]:
        continue
    scores["val" if sp == 1 else "train"].append(d)


def short_q(d):
    """The 10th percentile of the written note lengths in quarters (`corpus::perform`)."""
    ds = sorted(n["dur_q"] for n in d["notes"])
    return max(ds[len(ds) // 10], 1 / 16)


def excerpt(d, rng):
    """A run of bars of score `d` performed at a drawn tempo: notes in seconds, and the truth."""
    num, den = ts_of(d)
    bpb, beat_q = meter(num, den)
    bars = d["bars"]
    tq = d.get("tempo_qpm")
    bpm_mark = tq / beat_q if tq else None
    target_s = rng.uniform(8, 40)
    bar_s = 60.0 / (bpm_mark or 100.0) * bpb
    want = min(max(round(target_s / max(bar_s, 0.1)), 4), 48)
    n = len(bars)
    nb = min(want, n)
    first = rng.randint(0, n - nb) if n > nb else 0
    q0 = bars[first]["start_q"]
    q1 = bars[first + nb - 1]["start_q"] + bars[first + nb - 1]["len_q"]
    drawn = math.exp(math.log(40) + rng.random() * (math.log(200) - math.log(40)))
    bpm = bpm_mark * rng.uniform(0.85, 1.15) if bpm_mark else drawn
    bpm = min(bpm, 13 * 60 * short_q(d) / beat_q)
    bpm = min(max(bpm, 40), 200)
    spq = 60.0 / bpm / beat_q  # seconds per quarter
    notes = [n for n in d["notes"] if q0 <= n["start_q"] < q1 and n["midi"]]
    if len(notes) < 6:
        return None
    on = np.array([(n["start_q"] - q0) * spq for n in notes])
    du = np.array([n["dur_q"] * spq for n in notes])
    pi = np.array([max(n["midi"]) for n in notes], float)
    return dict(
        on=on, du=du, pi=pi, bpb=bpb, beat_s=60.0 / bpm, ts=f"{num}/{den}", coll=d["collection"]
    )


def pick_by_meter(pool, rng):
    """A score drawn as `corpus::schedule::pick_by_meter` does: time signature by sqrt(count)."""
    g = collections.defaultdict(list)
    for d in pool:
        g[ts_of(d)].append(d)
    keys = sorted(g)
    w = [math.sqrt(len(g[k])) for k in keys]
    k = rng.choices(keys, weights=w)[0]
    return rng.choice(g[k])


LAGS = [0.5, 1, 1.5, 2, 3, 4, 6, 8, 12, 16]


def features(x, use_pitch=True):
    """Notation-free features of an excerpt's notes, and its modal inter-onset interval (s)."""
    on, du, pi = x["on"], x["du"], x["pi"]
    ioi = np.diff(on)
    ioi = ioi[ioi > 1e-3]
    if len(ioi) == 0:
        return None
    # modal IOI (the grid unit) in log2 bins of 1/12 octave
    lg = np.round(np.log2(ioi) * 12)
    mode = 2 ** (collections.Counter(lg).most_common(1)[0][0] / 12)
    f = [math.log(len(on) / (on[-1] - on[0] + 1e-3)), math.log2(np.median(ioi)), math.log2(mode)]
    r = np.log2(ioi / mode)
    f += list(np.histogram(r, bins=np.arange(-2.125, 4.2, 0.25))[0] / len(r))
    f += list(np.histogram(np.log2(ioi), bins=np.arange(-4, 1.6, 0.5))[0] / len(r))
    rr = np.log2(ioi[1:] / ioi[:-1]) if len(ioi) > 1 else np.zeros(1)
    f += list(np.histogram(rr, bins=np.arange(-3.25, 3.3, 0.5))[0] / max(len(rr), 1))
    # onset autocorrelation at lags in multiples of the modal IOI (tempo-invariant)
    fs = 100.0
    T = int((on[-1] + du[-1]) * fs) + 2
    for w in (np.ones_like(du), np.log1p(du / mode)):
        s = np.zeros(T)
        idx = np.minimum((on * fs).astype(int), T - 1)
        np.add.at(s, idx, w)
        s = np.convolve(s, np.ones(5), "same")
        z = (s * s).sum() + 1e-9
        for k in LAGS:
            L = int(round(k * mode * fs))
            f.append((s[:-L] * s[L:]).sum() / z if 0 < L < T else 0.0)
    # long notes: share and their spacing in grid units
    long_ = on[du >= 1.9 * mode]
    f.append(len(long_) / len(on))
    if len(long_) > 1:
        g = np.diff(long_) / mode
        f += list(np.histogram(np.log2(g + 1e-9), bins=np.arange(-0.5, 5.1, 0.5))[0] / len(g))
    else:
        f += [0.0] * 11
    if use_pitch:
        iv = np.clip(np.diff(pi), -12, 12)
        f += list(np.histogram(iv, bins=np.arange(-12.5, 13))[0] / len(iv))
        f += [
            np.abs(iv).mean(),
            pi.max() - pi.min(),
            pi.std(),
            (np.abs(iv) <= 2).mean(),
            (iv == 0).mean(),
            pi.mean(),
        ]
        # pitch repetition at lags (in notes-on-grid time): similarity of pitch at t and t+L
        grid = np.interp(np.arange(0, on[-1], mode / 2), on, pi, left=pi[0], right=pi[-1])
        for k in LAGS[2:]:
            L = int(round(2 * k))
            f.append(np.mean(grid[:-L] == grid[L:]) if L < len(grid) else 0.0)
    return np.array(f, float), mode


def level_class(beat_s, mode):
    """The beat period as a multiple of the modal interval, in half-octave steps of log2."""
    return round(math.log2(beat_s / mode) * 2) / 2


COLLECTIONS = sorted({d["collection"] for d in scores["train"]})


def build(pool, n, rng, use_pitch, named=False):
    """`n` excerpts of `pool`: features, beats per bar, beat level, and (excerpt, mode)."""
    X, Y1, Y2, meta = [], [], [], []
    while len(X) < n:
        x = excerpt(pick_by_meter(pool, rng), rng)
        if x is None:
            continue
        r = features(x, use_pitch)
        if r is None:
            continue
        f, mode = r
        if named:  # the work's collection, one-hot: an oracle of style
            f = np.concatenate([f, [float(x["coll"] == c) for c in COLLECTIONS]])
        X.append(f)
        Y1.append(x["bpb"])
        Y2.append(level_class(x["beat_s"], mode))
        meta.append((x, mode))
    return np.array(X), np.array(Y1), np.array(Y2), meta


REGULARISED = dict(max_leaf_nodes=15, min_samples_leaf=200, l2_regularization=1.0)
# (name, pitch features, the collection named, tree settings)
CONFIGS = [
    ("rhythm only, regularised", False, False, REGULARISED),
    ("rhythm and pitch, regularised", True, False, REGULARISED),
    ("rhythm and pitch, scikit-learn's defaults", True, False, {}),
    ("rhythm and pitch and the collection's name, regularised", True, True, REGULARISED),
]


def share(flags):
    return round(float(np.mean(flags)), 2)


for name, use_pitch, named, extra in CONFIGS:
    Xt, bt, lt, _ = build(scores["train"], 8000, random.Random(82), use_pitch, named)
    Xv, bv, lv, mv = build(scores["val"], 2000, random.Random(83), use_pitch, named)

    def model():
        return HistGradientBoostingClassifier(
            max_iter=300, learning_rate=0.05, random_state=0, **extra
        )

    m1 = model().fit(Xt, bt)
    m2 = model().fit(Xt, lt.astype(str))
    pb = m1.predict(Xv)
    pl = m2.predict(Xv).astype(float)
    # tempo: the predicted beat (modal interval x 2**level) within 8 % of the notated one
    tempo_ok = np.array([abs(m * 2**p / x["beat_s"] - 1) <= 0.08 for p, (x, m) in zip(pl, mv)])
    prior_b = collections.Counter(bt).most_common(1)[0][0]
    prior_l = collections.Counter(lt).most_common(1)[0][0]
    print(
        f"## {name}: train {len(bt)} excerpts of {len(scores['train'])} works, "
        f"validation {len(bv)} of {len(scores['val'])} works"
    )
    print(
        f"  metre (beats per bar) right {np.mean(pb == bv):.3f} (always {prior_b}: "
        f"{np.mean(bv == prior_b):.3f}; on the training excerpts {np.mean(m1.predict(Xt) == bt):.3f})"
    )
    print(
        f"  beat level right {np.mean(pl == lv):.3f}, tempo within 8 % {tempo_ok.mean():.3f} "
        f"(always {prior_l}: {np.mean(lv == prior_l):.3f})"
    )
    by_ts = collections.defaultdict(list)
    for p, y, ok, (x, m) in zip(pb, bv, tempo_ok, mv):
        by_ts[x["ts"]].append((p == y, ok))
    print("  by time signature (excerpts, metre right, tempo right):")
    for ts, v in sorted(by_ts.items(), key=lambda kv: -len(kv[1])):
        print(f"    {ts}: {len(v)}, {share([a for a, _ in v])}, {share([b for _, b in v])}")
