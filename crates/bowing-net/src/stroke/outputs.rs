//! [`FrameOutputs`]: what the stroke network says about every frame.

/// The stroke network's probabilities for every frame of a recording.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameOutputs {
    /// Probability of a bow change at the frame.
    pub change: Vec<f32>,
    /// Probabilities of the four strings (G, D, A, E).
    pub string: Vec<[f32; 4]>,
    /// Probability that the bow moves down (frog to tip) at the frame (empty from the CNN).
    pub down: Vec<f32>,
}
