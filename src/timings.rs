//! [`StageTimings`]: where an analysis spends its time.

/// Seconds spent in each stage of an analysis (summed over chunks for long files).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimings {
    /// Decoding the file (only [`crate::Pipeline::analyze_file`] decodes).
    pub decode_s: f64,
    /// Resampling to the 22 050 Hz analysis rate.
    pub resample_s: f64,
    /// f0 tracking and note segmentation.
    pub pitch_s: f64,
    /// Beats, downbeats, metre and tempo (decoding; beat-net's activation is counted in
    /// `bowing_s`, which computes the shared mel spectrogram).
    pub beats_s: f64,
    /// The bow-change CNN (including loading its weights the first time).
    pub bowing_s: f64,
    /// The arousal CRNN (including loading its weights the first time).
    pub arousal_s: f64,
}

impl StageTimings {
    /// Adds another chunk's timings.
    pub fn add(&mut self, other: &StageTimings) {
        self.decode_s += other.decode_s;
        self.resample_s += other.resample_s;
        self.pitch_s += other.pitch_s;
        self.beats_s += other.beats_s;
        self.bowing_s += other.bowing_s;
        self.arousal_s += other.arousal_s;
    }

    /// The sum of all stages (more than the wall time: the score side and the networks run
    /// at once).
    pub fn total_s(&self) -> f64 {
        self.decode_s
            + self.resample_s
            + self.pitch_s
            + self.beats_s
            + self.bowing_s
            + self.arousal_s
    }
}

impl std::fmt::Display for StageTimings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "decode {:.3} s, resample {:.3} s, pitch+notes {:.3} s, beats {:.3} s, bowing-net {:.3} s, emotion-net {:.3} s",
            self.decode_s, self.resample_s, self.pitch_s, self.beats_s, self.bowing_s, self.arousal_s
        )
    }
}
