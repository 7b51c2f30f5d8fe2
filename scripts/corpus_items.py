"""Shared by the beat probes (bar_choice_ceiling.py, beats_after_end.py, bar_cues.py) and
compare_reports.py: reading a corpus item's label columns, the decoder's own reading of a
`beat_candidates` item, and the F-measure of event counts. Standard library only."""

# BarPointerConfig::bar_length_prior_per_frame (crates/beat-track), for bar lengths 1, 2, 3, 4.
DECODER_PRIOR = [-0.03, 0.01, 0.005, 0.0]


def column(path):
    """The first column of a label file (`beats.txt`, `downbeats.txt`, ...) as floats."""
    with open(path) as f:
        return [float(line.split()[0]) for line in f if line.strip()]


def shipped_choice(item):
    """The reading the shipped decoder picks among a `beat_candidates` item's decoded bar
    lengths: log-probability per frame plus the bar-length prior."""
    return max((c for c in item["candidates"] if c["kind"] == "decoded"),
               key=lambda c: c["log_p_per_frame"] + DECODER_PRIOR[c["prior_index"]])


def f_measure(matched, reference, estimated):
    """F-measure of matched events among `reference` labelled and `estimated` found ones."""
    return 2 * matched / max(reference + estimated, 1)
