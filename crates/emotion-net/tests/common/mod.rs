//! A seeded emotion-net for the integration tests.

use candle_core::{DType, Device};
use candle_nn::{VarBuilder, VarMap};
use emotion_net::{Config, EmotionNet};
use net_core::vars;

/// Parameters a test network leaves as `EmotionNet::new` made them, by name.
pub struct Keep<'a> {
    /// Names containing any of these (batch-norm running statistics always stay).
    pub containing: &'a [&'a str],
    /// Set every bias to 0 (as the trainer does) instead of drawing it.
    pub zero_biases: bool,
}

/// A network of `cfg` whose weights are drawn uniformly in ±√(3 / fan-in) from `seed`,
/// except the parameters `keep` names.
pub fn seeded_net(cfg: &Config, seed: u64, keep: &Keep<'_>) -> (VarMap, EmotionNet) {
    let varmap = VarMap::new();
    let net = EmotionNet::new(
        cfg,
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
    )
    .unwrap();
    vars::init_seeded(&varmap, seed, |n, d| {
        if n.starts_with("norm.")
            || n.contains("running_")
            || keep.containing.iter().any(|k| n.contains(k))
        {
            None
        } else if keep.zero_biases && n.contains("bias") {
            Some(0.0)
        } else {
            Some((3.0 / d.iter().skip(1).product::<usize>().max(1) as f64).sqrt())
        }
    })
    .unwrap();
    (varmap, net)
}
