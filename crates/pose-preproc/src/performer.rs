//! Choosing the performer among the people OpenPose found, and following them.
//!
//! OpenPose output often holds more than the violinist: a bystander, a reflection, a
//! one-frame false detection. The choice is track-based with hysteresis:
//!
//! 1. **Candidates.** A detection is a candidate when at least `min_confident_joints` of our
//!    ten joints have confidence ≥ the threshold. Its *score* is the mean confidence of the
//!    ten joints × the diagonal (px) of the bounding box of its confident joints, so large,
//!    confident people score high.
//! 2. **Start.** Over the first `start_frames` frames (from the first frame with a candidate;
//!    by default the whole clip), candidates are linked frame to frame into tracks (nearest first, one-to-one,
//!    within the step gate; a track unmatched for `reacquire_after_frames` ends). Each track's
//!    value is its *summed* score × (1 + `activity_weight` × its wrists' activity), the
//!    activity being the larger wrist's spread relative to the neck in units of the track's
//!    size (at most 0.5): a persistent person who plays beats a one-frame detection, a
//!    bystander who arrives later, and a still bystander up to about twice the performer's
//!    size.
//! 3. **Follow.** In every frame the candidate nearest to the performer's last known pose is
//!    the performer when its distance (mean over joints confident in both, at least 3) is at
//!    most `max_step_fraction` × the performer's size. Nobody else is ever taken while the
//!    performer is followed, however well they score (each such frame counts in
//!    [`PerformerStats::switches_rejected`]). A frame with no candidate near enough has no
//!    performer (its joints are then filled like any missing joint).
//! 4. **Re-acquire.** Only after `reacquire_after_frames` frames without the performer may a
//!    candidate elsewhere take over, and only if it scores at least `min_score_ratio` × the
//!    performer's usual score and can itself be followed through the next `confirm_frames`
//!    frames; otherwise it is rejected (and counted).

use serde::{Deserialize, Serialize};
use skeleton::{Joint, JOINT_COUNT};

use crate::config::PerformerConfig;
use crate::read::Detection;

/// Counts from the performer choice, for the quality report.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PerformerStats {
    /// Frames where no candidate was the performer.
    pub frames_without_performer: usize,
    /// Frames with at least one candidate other than the performer.
    pub frames_with_other_people: usize,
    /// Frames where a score-only choice would have taken someone else (a higher-scoring
    /// person next to the followed performer, or a re-acquisition candidate that failed).
    pub switches_rejected: usize,
    /// Times the performer was re-acquired at a new place after being lost.
    pub reacquisitions: usize,
}

/// Smoothing factor of the performer's running size and score.
const RUNNING_WEIGHT: f32 = 0.2;
/// Joints that must be confident in both poses for a distance.
const MIN_COMMON_JOINTS: usize = 3;

fn confident(d: &Detection, j: usize, threshold: f32) -> bool {
    d.joints[j][2] >= threshold && d.joints[j][2] > 0.0
}

/// Bounding-box diagonal (px) of the confident joints.
fn size(d: &Detection, threshold: f32) -> f32 {
    let mut lo = [f32::INFINITY; 2];
    let mut hi = [f32::NEG_INFINITY; 2];
    for j in (0..JOINT_COUNT).filter(|&j| confident(d, j, threshold)) {
        for c in 0..2 {
            lo[c] = lo[c].min(d.joints[j][c]);
            hi[c] = hi[c].max(d.joints[j][c]);
        }
    }
    if lo[0] > hi[0] {
        return 0.0;
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1])
}

/// Mean confidence of the ten joints × bounding-box diagonal.
fn score(d: &Detection, threshold: f32) -> f32 {
    let mean_conf = d.joints.iter().map(|p| p[2].clamp(0.0, 1.0)).sum::<f32>() / JOINT_COUNT as f32;
    mean_conf * size(d, threshold)
}

/// The last known pose of a followed person.
#[derive(Debug, Clone)]
struct Anchor {
    pos: [[f32; 2]; JOINT_COUNT],
    known: [bool; JOINT_COUNT],
    size: f32,
    score: f32,
    last_frame: usize,
}

impl Anchor {
    fn new(d: &Detection, threshold: f32, frame: usize) -> Self {
        let mut a = Anchor {
            pos: [[0.0; 2]; JOINT_COUNT],
            known: [false; JOINT_COUNT],
            size: size(d, threshold),
            score: score(d, threshold),
            last_frame: frame,
        };
        a.update(d, threshold, frame);
        a.size = size(d, threshold);
        a.score = score(d, threshold);
        a
    }

    fn update(&mut self, d: &Detection, threshold: f32, frame: usize) {
        for j in (0..JOINT_COUNT).filter(|&j| confident(d, j, threshold)) {
            self.pos[j] = [d.joints[j][0], d.joints[j][1]];
            self.known[j] = true;
        }
        self.size += RUNNING_WEIGHT * (size(d, threshold) - self.size);
        self.score += RUNNING_WEIGHT * (score(d, threshold) - self.score);
        self.last_frame = frame;
    }

    /// Mean distance over joints known here and confident in `d`.
    fn distance(&self, d: &Detection, threshold: f32) -> Option<f32> {
        let (mut sum, mut n) = (0.0f32, 0usize);
        for j in (0..JOINT_COUNT).filter(|&j| self.known[j] && confident(d, j, threshold)) {
            sum += (d.joints[j][0] - self.pos[j][0]).hypot(d.joints[j][1] - self.pos[j][1]);
            n += 1;
        }
        (n >= MIN_COMMON_JOINTS).then(|| sum / n as f32)
    }

    fn gate(&self, cfg: &PerformerConfig) -> f32 {
        cfg.max_step_fraction * self.size.max(1.0)
    }

    /// The candidate of `people` nearest to this pose within the gate.
    fn nearest(
        &self,
        people: &[Detection],
        cands: &[usize],
        threshold: f32,
        cfg: &PerformerConfig,
    ) -> Option<usize> {
        let gate = self.gate(cfg);
        let mut best: Option<(f32, usize)> = None;
        for &c in cands {
            if let Some(d) = self.distance(&people[c], threshold).filter(|d| *d <= gate) {
                if best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, c));
                }
            }
        }
        best.map(|(_, c)| c)
    }
}

/// Indices of the candidates of one frame.
fn candidates(people: &[Detection], threshold: f32, cfg: &PerformerConfig) -> Vec<usize> {
    (0..people.len())
        .filter(|&i| {
            (0..JOINT_COUNT)
                .filter(|&j| confident(&people[i], j, threshold))
                .count()
                >= cfg.min_confident_joints
        })
        .collect()
}

/// How much a short track's wrists move relative to its neck: per arm the sums of the
/// offset and its square, and the count; plus the summed size.
#[derive(Debug, Clone, Default)]
struct Activity {
    sum: [[f32; 2]; 2],
    sq: [[f32; 2]; 2],
    n: [f32; 2],
    size: f32,
    frames: f32,
}

impl Activity {
    fn add(&mut self, d: &Detection, threshold: f32) {
        let neck = Joint::Neck.index();
        self.size += size(d, threshold);
        self.frames += 1.0;
        if !confident(d, neck, threshold) {
            return;
        }
        for (a, w) in [Joint::RWrist, Joint::LWrist].into_iter().enumerate() {
            let w = w.index();
            if confident(d, w, threshold) {
                for c in 0..2 {
                    let v = d.joints[w][c] - d.joints[neck][c];
                    self.sum[a][c] += v;
                    self.sq[a][c] += v * v;
                }
                self.n[a] += 1.0;
            }
        }
    }

    /// The larger of the two wrists' spread (standard deviation of the offset to the neck)
    /// in units of the track's mean size, at most 0.5.
    fn level(&self) -> f32 {
        let mean_size = self.size / self.frames.max(1.0);
        let mut best = 0.0f32;
        for a in 0..2 {
            if self.n[a] < 3.0 {
                continue;
            }
            let var: f32 = (0..2)
                .map(|c| {
                    let m = self.sum[a][c] / self.n[a];
                    (self.sq[a][c] / self.n[a] - m * m).max(0.0)
                })
                .sum();
            best = best.max(var.sqrt() / mean_size.max(1.0));
        }
        best.min(0.5)
    }
}

/// The first pose of the best track in the first `start_frames` frames (step 2).
fn start_anchor(
    frames: &[Vec<Detection>],
    threshold: f32,
    cfg: &PerformerConfig,
) -> Option<Anchor> {
    let first = frames
        .iter()
        .position(|people| !candidates(people, threshold, cfg).is_empty())?;
    let end = frames.len().min(first.saturating_add(cfg.start_frames));
    // (current pose, summed score, first pose, wrist activity)
    let mut tracks: Vec<(Anchor, f32, Anchor, Activity)> = Vec::new();
    for (t, people) in frames.iter().enumerate().take(end).skip(first) {
        let cands = candidates(people, threshold, cfg);
        let mut pairs: Vec<(f32, usize, usize)> = Vec::new();
        for (i, (track, ..)) in tracks.iter().enumerate() {
            if t - track.last_frame > cfg.reacquire_after_frames {
                continue; // lost: a person appearing here later is someone new
            }
            for &c in &cands {
                if let Some(d) = track
                    .distance(&people[c], threshold)
                    .filter(|d| *d <= track.gate(cfg))
                {
                    pairs.push((d, i, c));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut track_used = vec![false; tracks.len()];
        let mut cand_used = vec![false; people.len()];
        for (_, i, c) in pairs {
            if !track_used[i] && !cand_used[c] {
                track_used[i] = true;
                cand_used[c] = true;
                tracks[i].0.update(&people[c], threshold, t);
                tracks[i].1 += score(&people[c], threshold);
                tracks[i].3.add(&people[c], threshold);
            }
        }
        for &c in cands.iter().filter(|&&c| !cand_used[c]) {
            let a = Anchor::new(&people[c], threshold, t);
            let mut activity = Activity::default();
            activity.add(&people[c], threshold);
            tracks.push((a.clone(), score(&people[c], threshold), a, activity));
        }
    }
    let mut best: Option<(f32, Anchor)> = None;
    for (_, total, start, activity) in tracks {
        let value = total * (1.0 + cfg.activity_weight * activity.level());
        if best.as_ref().is_none_or(|(b, _)| value > *b) {
            best = Some((value, start));
        }
    }
    best.map(|(_, a)| a)
}

/// True when a person starting at `c` in frame `t` can be followed through the next
/// `confirm_frames` frames (at most one of them without a match).
fn persists(
    frames: &[Vec<Detection>],
    t: usize,
    c: usize,
    threshold: f32,
    cfg: &PerformerConfig,
) -> bool {
    let mut anchor = Anchor::new(&frames[t][c], threshold, t);
    let mut misses = 0;
    let end = frames.len().min(t + 1 + cfg.confirm_frames);
    for (k, people) in frames.iter().enumerate().take(end).skip(t + 1) {
        let cands = candidates(people, threshold, cfg);
        match anchor.nearest(people, &cands, threshold, cfg) {
            Some(n) => anchor.update(&people[n], threshold, k),
            None => {
                misses += 1;
                if misses > 1 {
                    return false;
                }
            }
        }
    }
    true
}

/// For every frame, the index (into that frame's detections) of the performer, or `None`;
/// all `None` when no frame has a candidate. See the module documentation.
pub fn select_performer(
    frames: &[Vec<Detection>],
    threshold: f32,
    cfg: &PerformerConfig,
) -> (Vec<Option<usize>>, PerformerStats) {
    let mut chosen = vec![None; frames.len()];
    let mut stats = PerformerStats::default();
    let Some(mut anchor) = start_anchor(frames, threshold, cfg) else {
        stats.frames_without_performer = frames.len();
        return (chosen, stats);
    };
    for (t, people) in frames.iter().enumerate() {
        let cands = candidates(people, threshold, cfg);
        if let Some(c) = anchor.nearest(people, &cands, threshold, cfg) {
            chosen[t] = Some(c);
            if cands.len() > 1 {
                stats.frames_with_other_people += 1;
                let own = score(&people[c], threshold);
                if cands
                    .iter()
                    .any(|&o| o != c && score(&people[o], threshold) > own)
                {
                    stats.switches_rejected += 1;
                }
            }
            anchor.update(&people[c], threshold, t);
            continue;
        }
        let lost_for = t.saturating_sub(anchor.last_frame);
        if lost_for > cfg.reacquire_after_frames && !cands.is_empty() {
            let mut by_score = cands.clone();
            by_score.sort_by(|&a, &b| {
                score(&people[b], threshold).total_cmp(&score(&people[a], threshold))
            });
            let min_score = cfg.min_score_ratio * anchor.score;
            let taken = by_score.into_iter().find(|&c| {
                score(&people[c], threshold) >= min_score && persists(frames, t, c, threshold, cfg)
            });
            match taken {
                Some(c) => {
                    chosen[t] = Some(c);
                    stats.reacquisitions += 1;
                    anchor = Anchor::new(&people[c], threshold, t);
                    continue;
                }
                None => stats.switches_rejected += 1,
            }
        }
        if !cands.is_empty() {
            stats.frames_with_other_people += 1;
        }
        stats.frames_without_performer += 1;
    }
    (chosen, stats)
}
