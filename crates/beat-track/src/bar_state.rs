//! The bar-pointer state space of one bar length and its Viterbi decoding (Krebs, Böck &
//! Widmer 2015; madmom's `BarStateSpace`, `BarTransitionModel` and
//! `RNNDownBeatTrackingObservationModel`), for [`crate::bar_pointer`].
//!
//! A state is (tempo, beat of the bar, position in the beat): the tempo is a beat interval
//! of `interval` frames, the position counts frames since the beat started. Inside a beat
//! the pointer moves one position per frame; from a beat's last position it moves to the
//! first position of the next beat (the bar's first after its last) at any tempo, paying
//! `−λ·|new/old − 1|` (normalised per old tempo; negligible moves are dropped, so the
//! transitions stay sparse). The first positions of a beat (1/`observation_lambda` of it, at
//! least one frame) "see" a beat — a downbeat on the bar's first beat — and the others see
//! no beat.

/// Log-probabilities below this are treated as impossible transitions.
const MIN_LOG_TRANSITION: f64 = -16.0;

/// A tempo's predecessors as a contiguous window: its first tempo and the log-probabilities
/// from there on (−∞ where a transition inside the window was dropped).
fn window(pairs: Vec<(usize, f64)>) -> (usize, Vec<f64>) {
    let first = pairs.iter().map(|p| p.0).min().unwrap_or(0);
    let last = pairs.iter().map(|p| p.0).max().unwrap_or(0);
    let len = if pairs.is_empty() {
        0
    } else {
        last - first + 1
    };
    let mut lps = vec![f64::NEG_INFINITY; len];
    for (qf, lp) in pairs {
        lps[qf - first] = lp;
    }
    (first, lps)
}

/// Per-frame log-likelihoods of the three observations.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameObservation {
    pub(crate) none: f32,
    pub(crate) beat: f32,
    pub(crate) downbeat: f32,
}

/// One decoded frame: which beat of the bar, which tempo (interval in frames) and whether
/// a beat starts there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PathFrame {
    pub(crate) beat_of_bar: usize,
    pub(crate) interval: usize,
    pub(crate) beat_starts: bool,
}

/// The state space of bars of `beats` beats.
pub(crate) struct BarStateSpace {
    beats: usize,
    intervals: Vec<usize>,
    /// First state of block (tempo q, beat b) at `offsets[q * beats + b]`.
    offsets: Vec<usize>,
    /// Frames of each beat that observe a beat, per tempo.
    region: Vec<usize>,
    /// For every tempo q, the previous tempi that may precede it: the first one, and the
    /// log-probabilities of it and the following ones (a contiguous window; −∞ for a
    /// dropped transition inside it). The log-probability is rounded to `f32`, held as
    /// `f64`.
    incoming: Vec<(usize, Vec<f64>)>,
    /// Whether block k is a bar's first beat.
    downbeat_block: Vec<bool>,
    states: usize,
}

impl BarStateSpace {
    /// The space for `beats` beats per bar and beat intervals `intervals` (frames, sorted,
    /// each ≥ 1), of which the first `region[q]` frames of a beat at interval q observe a
    /// beat (each in 1..=interval).
    pub(crate) fn new(
        beats: usize,
        intervals: &[usize],
        transition_lambda: f64,
        region: &[usize],
    ) -> Self {
        let mut offsets = Vec::with_capacity(intervals.len() * beats);
        let mut states = 0;
        for &i in intervals {
            for _ in 0..beats {
                offsets.push(states);
                states += i;
            }
        }
        // exp(−λ|to/from − 1|), normalised over `to` for every `from`.
        let mut incoming: Vec<Vec<(usize, f64)>> = vec![Vec::new(); intervals.len()];
        for (qf, &from) in intervals.iter().enumerate() {
            let raw: Vec<f64> = intervals
                .iter()
                .map(|&to| -transition_lambda * (to as f64 / from as f64 - 1.0).abs())
                .collect();
            let max = raw.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let norm = max + raw.iter().map(|v| (v - max).exp()).sum::<f64>().ln();
            for (qt, v) in raw.iter().enumerate() {
                let lp = v - norm;
                if lp >= MIN_LOG_TRANSITION {
                    incoming[qt].push((qf, f64::from(lp as f32)));
                }
            }
        }
        let incoming = incoming.into_iter().map(window).collect();
        Self {
            downbeat_block: (0..offsets.len()).map(|k| k % beats == 0).collect(),
            beats,
            intervals: intervals.to_vec(),
            offsets,
            region: region.to_vec(),
            incoming,
            states,
        }
    }

    /// The most likely path and its log-probability; with `keep_path` false only the
    /// log-probability (the path comes back empty, and no back-pointers are stored).
    ///
    /// Each (tempo, beat) block of states is a ring buffer with an additive offset: moving
    /// every pointer one position on is moving the ring's head, and the "no beat"
    /// observation that most positions see is added to the offset, so a frame costs the
    /// beat-boundary transitions and the few beat positions, not a pass over all states.
    pub(crate) fn viterbi(
        &self,
        obs: &[FrameObservation],
        keep_path: bool,
    ) -> (f64, Vec<PathFrame>) {
        if keep_path {
            self.viterbi_with::<true>(obs)
        } else {
            self.viterbi_with::<false>(obs)
        }
    }

    /// [`Self::viterbi`], compiled apart for `KEEP_PATH` so that the score-only decoding
    /// does not track its best predecessors.
    fn viterbi_with<const KEEP_PATH: bool>(
        &self,
        obs: &[FrameObservation],
    ) -> (f64, Vec<PathFrame>) {
        let (nq, nb) = (self.intervals.len(), self.beats);
        if obs.is_empty() || self.states == 0 {
            return (f64::NEG_INFINITY, Vec::new());
        }
        let blocks = nq * nb;
        let len = |k: usize| self.intervals[k / nb];
        let beat_obs = |o: &FrameObservation, k: usize| {
            f64::from(if self.downbeat_block[k] {
                o.downbeat
            } else {
                o.beat
            })
        };
        // Slot of position p in block k is offsets[k] + (head[k] + p) % len.
        let mut raw = vec![0.0f64; self.states];
        // A uniform start.
        let mut base = vec![f64::from(obs[0].none); blocks];
        let mut head = vec![0usize; blocks];
        for (k, &off) in self.offsets.iter().enumerate() {
            for p in 0..self.region[k / nb] {
                raw[off + p] = beat_obs(&obs[0], k) - base[k];
            }
        }
        let mut firsts = vec![0.0f64; blocks];
        // The value of every block's last position (the one that moves to the next beat).
        let mut lasts = vec![0.0f64; blocks];
        // The predecessor tempo of every beat start, per frame.
        let mut back = vec![0u16; if KEEP_PATH { obs.len() * blocks } else { 0 }];
        // Block k = q·nb + b; the loops run over q and b so that no index is divided.
        let block_len: Vec<usize> = (0..blocks).map(len).collect();
        let region: Vec<usize> = (0..blocks).map(|k| self.region[k / nb]).collect();
        for (t, o) in obs.iter().enumerate().skip(1) {
            for q in 0..nq {
                for b in 0..nb {
                    let k = q * nb + b;
                    let slot = if head[k] == 0 {
                        block_len[k] - 1
                    } else {
                        head[k] - 1
                    };
                    // Beat-major, so that a tempo's predecessors are adjacent.
                    lasts[b * nq + q] = raw[self.offsets[k] + slot] + base[k];
                }
            }
            let mut back_t = back.get_mut(t * blocks..(t + 1) * blocks);
            for b in 0..nb {
                let prev_beat = if b == 0 { nb - 1 } else { b - 1 };
                let prev = &lasts[prev_beat * nq..(prev_beat + 1) * nq];
                for (q, (first, lps)) in self.incoming.iter().enumerate() {
                    let from = prev.get(*first..first + lps.len()).unwrap_or(&[]);
                    let mut best = f64::NEG_INFINITY;
                    let mut arg = 0usize;
                    for (j, (&last, &lp)) in from.iter().zip(lps).enumerate() {
                        let v = last + lp;
                        // Branch-free (the comparison is unpredictable); not `f64::max`:
                        // no value here is NaN (−∞ at worst), and the plain comparison
                        // compiles to one `maxsd`.
                        let better = v > best;
                        best = if better { v } else { best };
                        if KEEP_PATH {
                            arg = if better { first + j } else { arg };
                        }
                    }
                    if let Some(back_t) = back_t.as_deref_mut() {
                        back_t[q * nb + b] = arg as u16;
                    }
                    firsts[q * nb + b] = best;
                }
            }
            let none = f64::from(o.none);
            let (beat_on, down_on) = (f64::from(o.beat), f64::from(o.downbeat));
            for k in 0..blocks {
                let (off, l) = (self.offsets[k], block_len[k]);
                let on = if self.downbeat_block[k] {
                    down_on
                } else {
                    beat_on
                };
                head[k] = if head[k] == 0 { l - 1 } else { head[k] - 1 };
                base[k] += none;
                raw[off + head[k]] = firsts[k] + on - base[k];
                let mut slot = head[k];
                for _ in 1..region[k] {
                    slot = if slot + 1 == l { 0 } else { slot + 1 };
                    raw[off + slot] += on - none;
                }
            }
        }
        let mut best = (0usize, f64::NEG_INFINITY);
        for k in 0..blocks {
            let (off, l) = (self.offsets[k], len(k));
            for p in 0..l {
                let v = raw[off + (head[k] + p) % l] + base[k];
                if v > best.1 {
                    best = (off + p, v);
                }
            }
        }
        let (mut state, score) = best;
        if !KEEP_PATH {
            return (score, Vec::new());
        }
        let mut path = vec![
            PathFrame {
                beat_of_bar: 0,
                interval: 0,
                beat_starts: false
            };
            obs.len()
        ];
        for t in (0..obs.len()).rev() {
            let (q, b, p) = self.locate(state);
            path[t] = PathFrame {
                beat_of_bar: b,
                interval: self.intervals[q],
                beat_starts: p == 0,
            };
            if t == 0 {
                break;
            }
            state = if p > 0 {
                state - 1
            } else {
                let qf = usize::from(back[t * blocks + q * nb + b]);
                let prev_beat = (b + nb - 1) % nb;
                self.offsets[qf * nb + prev_beat] + self.intervals[qf] - 1
            };
        }
        (score, path)
    }

    /// (tempo, beat, position) of a state.
    fn locate(&self, state: usize) -> (usize, usize, usize) {
        let k = self.offsets.partition_point(|&o| o <= state) - 1;
        (k / self.beats, k % self.beats, state - self.offsets[k])
    }
}
