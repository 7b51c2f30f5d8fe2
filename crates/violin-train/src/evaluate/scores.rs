//! What `evaluate` measures per recording and how recordings are pooled (SPEC §10).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// Matched / reference / estimated counts of an event detector, pooled over recordings
/// (micro-averaged, as mir_eval-style reports pool their counts).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct EventCounts {
    /// Estimated events matched one-to-one to a reference event within the tolerance.
    pub matched: usize,
    /// Reference events.
    pub reference: usize,
    /// Estimated events.
    pub estimated: usize,
}

impl EventCounts {
    /// Counts of `estimated_s` against `reference_s` with a `tolerance_s` window (one-to-one
    /// matching, mir_eval's `match_events`).
    pub fn of(reference_s: &[f64], estimated_s: &[f64], tolerance_s: f64) -> Self {
        Self {
            matched: pitch_track::eval::match_events(reference_s, estimated_s, tolerance_s).len(),
            reference: reference_s.len(),
            estimated: estimated_s.len(),
        }
    }

    /// Adds another recording's counts.
    pub fn add(&mut self, other: &EventCounts) {
        self.matched += other.matched;
        self.reference += other.reference;
        self.estimated += other.estimated;
    }

    /// Share of estimated events that are right (1 when nothing was estimated).
    pub fn precision(&self) -> f64 {
        if self.estimated == 0 {
            1.0
        } else {
            self.matched as f64 / self.estimated as f64
        }
    }

    /// Share of reference events found (1 when there is none).
    pub fn recall(&self) -> f64 {
        if self.reference == 0 {
            1.0
        } else {
            self.matched as f64 / self.reference as f64
        }
    }

    /// Harmonic mean of precision and recall (0 when both are 0).
    pub fn f1(&self) -> f64 {
        let (p, r) = (self.precision(), self.recall());
        if p + r == 0.0 {
            0.0
        } else {
            2.0 * p * r / (p + r)
        }
    }
}

/// Every SPEC §10 measure of one recording. A measure is `None` when the dataset has no
/// reference for it (e.g. beats in URMP) or the method does not produce it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordingScores {
    /// Item folder or track file name.
    pub name: String,
    /// `builtin`, `soundfont` (corpus renderers) or `urmp`.
    pub group: String,
    /// Length in seconds.
    pub duration_s: f64,
    /// Bow changes at ±2 frames (±66.7 ms).
    pub bow_changes_2f: Option<EventCounts>,
    /// Bow changes at ±3 frames (±100 ms).
    pub bow_changes_3f: Option<EventCounts>,
    /// Share of reference-voiced f0 frames within ±50 cents (corpus: frames within 30 ms of
    /// a labelled note edge and release tails are not scored).
    pub raw_pitch_accuracy: Option<f64>,
    /// Share of reference-voiced frames estimated voiced.
    pub voicing_recall: Option<f64>,
    /// Share of reference-unvoiced frames estimated voiced.
    pub voicing_false_alarm: Option<f64>,
    /// Note onsets at ±50 ms.
    pub onsets: Option<EventCounts>,
    /// Beats at ±70 ms (the first 5 s ignored, as mir_eval does).
    pub beats: Option<EventCounts>,
    /// Downbeats at ±70 ms (the first 5 s ignored).
    pub downbeats: Option<EventCounts>,
    /// Whether the beats per bar found are the notated ones.
    #[serde(default)]
    pub meter_correct: Option<bool>,
    /// Whether the tempo found is within 8 % of the notated beat's tempo.
    #[serde(default)]
    pub tempo_correct: Option<bool>,
    /// Whether the tempo found is within 8 % of twice or half the notated tempo.
    #[serde(default)]
    pub tempo_octave_error: Option<bool>,
    /// Mean absolute joint error to the reference skeleton in pixels (same camera), when
    /// the reference shares the image space (corpus).
    pub skeleton_l1_px: Option<f64>,
    /// The same for the right (bowing) wrist.
    pub right_wrist_l1_px: Option<f64>,
    /// Mean absolute joint error after centring both skeletons and scaling them to a unit
    /// mean shoulder width (comparable across cameras, e.g. against OpenPose in URMP).
    pub skeleton_l1_shoulders: Option<f64>,
    /// Mean |acceleration| of the joints, px/frame².
    pub jitter_px: f64,
    /// Largest coefficient of variation of a bone's length on the 2-D track, over bones (the
    /// projection foreshortens: the corpus's own motion reads about 0.3).
    pub bone_length_cv: f64,
    /// Bowing attacks read off the skeleton (right-wrist velocity reversals, Kao & Su 2020)
    /// against the reference bow changes, ±3 frames: works for both methods.
    pub bowing_attacks_3f: Option<EventCounts>,
    /// Share of frames whose bow position leaves the bow (Method 2 only).
    pub bow_range_violations: Option<f64>,
    /// Beat alignment score in [0, 1]: motion speed minima near the reference beats.
    pub beat_alignment: Option<f64>,
    /// Share of sounding frames with the bow hair within 5 mm of the played string between
    /// bridge and fingerboard (Method 2, 3-D).
    #[serde(default)]
    pub bow_string_contact: Option<f64>,
    /// Share of stopped-note frames with the playing fingertip within 5 mm of its string
    /// (Method 2, 3-D).
    #[serde(default)]
    pub fingertip_string_contact: Option<f64>,
    /// Mean |acceleration| of the 42 hand points, px/frame² (when the motion has hands).
    #[serde(default)]
    pub hand_jitter_px: Option<f64>,
    /// Labelled strokes whose direction the analysis gets right (corpus only).
    #[serde(default)]
    pub stroke_directions: Option<super::Tally>,
    /// Sounding frames whose string the analysis's strokes get right (corpus only).
    #[serde(default)]
    pub sounding_strings: Option<super::Tally>,
    /// Seconds the pipeline took on this recording (analysis and synthesis).
    pub seconds: f64,
}

/// Pooled figures of a set of recordings: event counts summed, frame and motion measures
/// averaged with each recording weighted by its duration.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ScoreSummary {
    /// Recordings pooled.
    pub recordings: usize,
    /// Their total length in seconds.
    pub duration_s: f64,
    /// Bow-change precision at ±2 frames.
    pub bow_change_precision: Option<f64>,
    /// Bow-change recall at ±2 frames.
    pub bow_change_recall: Option<f64>,
    /// Bow-change F1 at ±2 frames (SPEC §10).
    pub bow_change_f1: Option<f64>,
    /// Bow-change F1 at ±3 frames.
    pub bow_change_f1_3f: Option<f64>,
    /// Raw pitch accuracy (±50 cents).
    pub raw_pitch_accuracy: Option<f64>,
    /// Voicing recall.
    pub voicing_recall: Option<f64>,
    /// Voicing false alarm.
    pub voicing_false_alarm: Option<f64>,
    /// Note-onset F1 (±50 ms).
    pub onset_f1: Option<f64>,
    /// Beat F-measure (±70 ms).
    pub beat_f: Option<f64>,
    /// Downbeat F-measure (±70 ms).
    pub downbeat_f: Option<f64>,
    /// Share of recordings with the notated beats per bar.
    #[serde(default)]
    pub meter_accuracy: Option<f64>,
    /// Share of recordings with the tempo within 8 % of the notated level.
    #[serde(default)]
    pub tempo_accuracy: Option<f64>,
    /// Share of recordings with the tempo at twice or half the notated level (±8 %).
    #[serde(default)]
    pub tempo_octave_errors: Option<f64>,
    /// Skeleton L1 in pixels.
    pub skeleton_l1_px: Option<f64>,
    /// Right-wrist L1 in pixels.
    pub right_wrist_l1_px: Option<f64>,
    /// Skeleton L1 in shoulder widths.
    pub skeleton_l1_shoulders: Option<f64>,
    /// Jitter, px/frame².
    pub jitter_px: Option<f64>,
    /// Bone-length coefficient of variation.
    pub bone_length_cv: Option<f64>,
    /// Bow hair–string contact share (sounding frames).
    #[serde(default)]
    pub bow_string_contact: Option<f64>,
    /// Fingertip–string contact share (stopped-note frames).
    #[serde(default)]
    pub fingertip_string_contact: Option<f64>,
    /// Hand jitter, px/frame².
    #[serde(default)]
    pub hand_jitter_px: Option<f64>,
    /// Bowing-attack F1 (±3 frames) of the skeleton against the bow changes.
    pub bowing_attack_f1: Option<f64>,
    /// Share of labelled strokes with the right direction.
    #[serde(default)]
    pub stroke_direction_accuracy: Option<f64>,
    /// Share of sounding frames with the right string.
    #[serde(default)]
    pub string_accuracy: Option<f64>,
    /// Share of frames with the bow out of range.
    pub bow_range_violations: Option<f64>,
    /// Beat alignment score.
    pub beat_alignment: Option<f64>,
    /// Audio seconds processed per second of pipeline time.
    pub times_real_time: Option<f64>,
}

fn pooled_counts(
    rows: &[&RecordingScores],
    get: impl Fn(&RecordingScores) -> Option<EventCounts>,
) -> Option<EventCounts> {
    let mut total: Option<EventCounts> = None;
    for c in rows.iter().filter_map(|r| get(r)) {
        total.get_or_insert_with(EventCounts::default).add(&c);
    }
    total
}

fn pooled_tally(
    rows: &[&RecordingScores],
    get: impl Fn(&RecordingScores) -> Option<super::Tally>,
) -> Option<f64> {
    let mut total: Option<super::Tally> = None;
    for t in rows.iter().filter_map(|r| get(r)) {
        total.get_or_insert_with(super::Tally::default).add(&t);
    }
    total.map(|t| t.share())
}

/// The share of `rows` for which `get` says yes, among those where it says anything.
fn share(rows: &[&RecordingScores], get: impl Fn(&RecordingScores) -> Option<bool>) -> Option<f64> {
    let answers: Vec<bool> = rows.iter().filter_map(|r| get(r)).collect();
    (!answers.is_empty())
        .then(|| answers.iter().filter(|a| **a).count() as f64 / answers.len() as f64)
}

fn weighted_mean(
    rows: &[&RecordingScores],
    get: impl Fn(&RecordingScores) -> Option<f64>,
) -> Option<f64> {
    let (mut sum, mut weight) = (0.0, 0.0);
    for r in rows {
        if let Some(v) = get(r).filter(|v| v.is_finite()) {
            sum += v * r.duration_s;
            weight += r.duration_s;
        }
    }
    (weight > 0.0).then(|| sum / weight)
}

impl ScoreSummary {
    /// Pools `rows`.
    pub fn of(rows: &[&RecordingScores]) -> Self {
        let bow2 = pooled_counts(rows, |r| r.bow_changes_2f);
        let duration_s: f64 = rows.iter().map(|r| r.duration_s).sum();
        let seconds: f64 = rows.iter().map(|r| r.seconds).sum();
        Self {
            recordings: rows.len(),
            duration_s,
            bow_change_precision: bow2.map(|c| c.precision()),
            bow_change_recall: bow2.map(|c| c.recall()),
            bow_change_f1: bow2.map(|c| c.f1()),
            bow_change_f1_3f: pooled_counts(rows, |r| r.bow_changes_3f).map(|c| c.f1()),
            raw_pitch_accuracy: weighted_mean(rows, |r| r.raw_pitch_accuracy),
            voicing_recall: weighted_mean(rows, |r| r.voicing_recall),
            voicing_false_alarm: weighted_mean(rows, |r| r.voicing_false_alarm),
            onset_f1: pooled_counts(rows, |r| r.onsets).map(|c| c.f1()),
            beat_f: pooled_counts(rows, |r| r.beats).map(|c| c.f1()),
            downbeat_f: pooled_counts(rows, |r| r.downbeats).map(|c| c.f1()),
            meter_accuracy: share(rows, |r| r.meter_correct),
            tempo_accuracy: share(rows, |r| r.tempo_correct),
            tempo_octave_errors: share(rows, |r| r.tempo_octave_error),
            skeleton_l1_px: weighted_mean(rows, |r| r.skeleton_l1_px),
            right_wrist_l1_px: weighted_mean(rows, |r| r.right_wrist_l1_px),
            skeleton_l1_shoulders: weighted_mean(rows, |r| r.skeleton_l1_shoulders),
            jitter_px: weighted_mean(rows, |r| Some(r.jitter_px)),
            bone_length_cv: weighted_mean(rows, |r| Some(r.bone_length_cv)),
            bow_string_contact: weighted_mean(rows, |r| r.bow_string_contact),
            fingertip_string_contact: weighted_mean(rows, |r| r.fingertip_string_contact),
            hand_jitter_px: weighted_mean(rows, |r| r.hand_jitter_px),
            bowing_attack_f1: pooled_counts(rows, |r| r.bowing_attacks_3f).map(|c| c.f1()),
            stroke_direction_accuracy: pooled_tally(rows, |r| r.stroke_directions),
            string_accuracy: pooled_tally(rows, |r| r.sounding_strings),
            bow_range_violations: weighted_mean(rows, |r| r.bow_range_violations),
            beat_alignment: weighted_mean(rows, |r| r.beat_alignment),
            times_real_time: (seconds > 0.0).then(|| duration_s / seconds),
        }
    }
}

/// The report `violin-skeleton evaluate` writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EvaluationReport {
    /// The dataset folder.
    pub dataset: String,
    /// `corpus` or `urmp`.
    pub layout: String,
    /// The split evaluated (`test`, `val`, `train` or `all`).
    pub split: String,
    /// `rules` (Method 2) or `gru` (Method 1).
    pub method: String,
    /// Every recording pooled.
    pub overall: ScoreSummary,
    /// Pooled per group (renderer for a corpus).
    pub groups: BTreeMap<String, ScoreSummary>,
    /// Per recording.
    pub recordings: Vec<RecordingScores>,
}

impl EvaluationReport {
    /// Pools `recordings` overall and per group.
    pub fn new(
        dataset: String,
        layout: &str,
        split: &str,
        method: &str,
        recordings: Vec<RecordingScores>,
    ) -> Self {
        let all: Vec<&RecordingScores> = recordings.iter().collect();
        let mut groups = BTreeMap::new();
        let mut names: Vec<&str> = recordings.iter().map(|r| r.group.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        for g in names {
            let rows: Vec<&RecordingScores> = recordings.iter().filter(|r| r.group == g).collect();
            groups.insert(g.to_string(), ScoreSummary::of(&rows));
        }
        Self {
            dataset,
            layout: layout.into(),
            split: split.into(),
            method: method.into(),
            overall: ScoreSummary::of(&all),
            groups,
            recordings,
        }
    }

    /// A plain-text table: one column per group and one for everything.
    pub fn table(&self) -> String {
        // Held-out sets first, in-distribution last, then everything.
        let rank = |k: &str| match k {
            "held-out both" => 0,
            "held-out repertoire" => 1,
            "held-out violin" => 2,
            "in-distribution" => 3,
            "val works" => 4,
            "val études" => 5,
            _ => 6,
        };
        let mut cols: Vec<(&str, &ScoreSummary)> =
            self.groups.iter().map(|(k, v)| (k.as_str(), v)).collect();
        cols.sort_by_key(|(k, _)| rank(k));
        cols.push(("all", &self.overall));
        // (label, value, decimals; `None` decimals = scientific notation)
        type Row = (
            &'static str,
            fn(&ScoreSummary) -> Option<f64>,
            Option<usize>,
        );
        let rows: [Row; 24] = [
            ("recordings", |s| Some(s.recordings as f64), Some(0)),
            ("minutes", |s| Some(s.duration_s / 60.0), Some(1)),
            ("bow-change P ±2 fr", |s| s.bow_change_precision, Some(3)),
            ("bow-change R ±2 fr", |s| s.bow_change_recall, Some(3)),
            ("bow-change F1 ±2 fr", |s| s.bow_change_f1, Some(3)),
            ("bow-change F1 ±3 fr", |s| s.bow_change_f1_3f, Some(3)),
            ("stroke direction", |s| s.stroke_direction_accuracy, Some(3)),
            ("string, sounding frames", |s| s.string_accuracy, Some(3)),
            ("raw pitch accuracy", |s| s.raw_pitch_accuracy, Some(3)),
            ("note-onset F1 ±50 ms", |s| s.onset_f1, Some(3)),
            ("beat F ±70 ms", |s| s.beat_f, Some(3)),
            ("downbeat F ±70 ms", |s| s.downbeat_f, Some(3)),
            ("meter correct", |s| s.meter_accuracy, Some(3)),
            ("tempo within 8 %", |s| s.tempo_accuracy, Some(3)),
            ("tempo ×2 or ×½", |s| s.tempo_octave_errors, Some(3)),
            ("skeleton L1 px", |s| s.skeleton_l1_px, Some(1)),
            ("right-wrist L1 px", |s| s.right_wrist_l1_px, Some(1)),
            (
                "skeleton L1 shoulders",
                |s| s.skeleton_l1_shoulders,
                Some(3),
            ),
            ("jitter px/frame²", |s| s.jitter_px, Some(2)),
            ("bone-length CV, 2-D", |s| s.bone_length_cv, Some(3)),
            ("bowing-attack F1 ±3 fr", |s| s.bowing_attack_f1, Some(3)),
            ("bow-range violations", |s| s.bow_range_violations, Some(3)),
            ("beat alignment", |s| s.beat_alignment, Some(3)),
            ("× real time", |s| s.times_real_time, Some(0)),
        ];
        let mut out = format!("{:<24}", "");
        for (name, _) in &cols {
            let short = name
                .replace("held-out ", "ho-")
                .replace("in-distribution", "in-dist");
            out.push_str(&format!("{short:>14}"));
        }
        out.push('\n');
        for (label, get, digits) in rows {
            out.push_str(&format!("{label:<24}"));
            for (_, s) in &cols {
                match (get(s), digits) {
                    (Some(v), Some(d)) => out.push_str(&format!("{v:>14.d$}")),
                    (Some(v), None) => out.push_str(&format!("{v:>14.1e}")),
                    (None, _) => out.push_str(&format!("{:>14}", "—")),
                }
            }
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_pool_as_micro_averages() {
        let mut a = EventCounts::of(&[1.0, 2.0, 3.0], &[1.01, 2.5], 0.05);
        assert_eq!((a.matched, a.reference, a.estimated), (1, 3, 2));
        a.add(&EventCounts::of(&[1.0], &[1.0], 0.05));
        assert_eq!((a.matched, a.reference, a.estimated), (2, 4, 3));
        assert!((a.f1() - 2.0 * (2.0 / 3.0) * 0.5 / (2.0 / 3.0 + 0.5)).abs() < 1e-12);
        assert_eq!(EventCounts::default().f1(), 1.0);
        let none_found = EventCounts {
            matched: 0,
            reference: 3,
            estimated: 0,
        };
        assert_eq!(none_found.f1(), 0.0);
    }
}
