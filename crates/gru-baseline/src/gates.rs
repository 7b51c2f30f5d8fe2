//! The GRU's gate arithmetic on plain f32 slices, shared by the recurrence's forward and
//! backward loops: a vectorisable `eˣ`, the logistic and `tanh` built on it, the folded
//! biases, and one step of one batch row.

/// `eˣ` for f32 without a library call, so loops over it vectorise: `x = n·ln 2 + r`,
/// `|r| ≤ ln 2 / 2`, Cephes' degree-6 polynomial for `eʳ`, `2ⁿ` built in the exponent bits
/// (within 2 ulp of `f32::exp` on [-87, 88]; clamped outside).
#[inline(always)]
pub(crate) fn fast_exp(x: f32) -> f32 {
    let x = x.clamp(-87.0, 88.0);
    let n = (x * std::f32::consts::LOG2_E + 0.5).floor();
    let r = x - n * 0.693_359_4 + n * 2.121_944_4e-4;
    let mut p = 1.987_569_1e-4_f32;
    p = p * r + 1.398_199_9e-3;
    p = p * r + 8.333_452e-3;
    p = p * r + 4.166_579_6e-2;
    p = p * r + 1.666_666_5e-1;
    p = p * r + 0.5;
    let y = p * r * r + r + 1.0;
    // 2ⁿ: adding 1.5·2²³ puts the integer n in the low mantissa bits (no float→int
    // conversion, which would not vectorise); n + 127 ∈ [1, 254] is the biased exponent.
    let n_bits = (n + 12_582_912.0).to_bits().wrapping_sub(0x4B40_0000);
    y * f32::from_bits(n_bits.wrapping_add(127) << 23)
}

/// The logistic function.
#[inline(always)]
pub(crate) fn sigmoid(x: f32) -> f32 {
    1.0 / (1.0 + fast_exp(-x))
}

/// `tanh x = 1 − 2 / (e²ˣ + 1)` (absolute error below 1e-7).
#[inline(always)]
pub(crate) fn tanh(x: f32) -> f32 {
    1.0 - 2.0 / (fast_exp(2.0 * x) + 1.0)
}

/// One step of one row: the new state `h_new` from the input projection `x` `(3H)`, the
/// recurrent product `gh` `(3H)` (without `b_hh`) and the previous state.
#[inline(always)]
pub(crate) fn gate_row(x: &[f32], gh: &[f32], bias: &Biases, h_prev: &[f32], h_new: &mut [f32]) {
    let hidden = h_prev.len();
    let (xr, rest) = x.split_at(hidden);
    let (xz, xn) = rest.split_at(hidden);
    let (gr, rest) = gh.split_at(hidden);
    let (gz, gn) = rest.split_at(hidden);
    let (br, rest) = bias.rz.split_at(hidden);
    let bz = &rest[..hidden];
    let (bin, bhn) = (&bias.x_n[..hidden], &bias.h_n[..hidden]);
    for j in 0..hidden {
        let r = sigmoid(xr[j] + gr[j] + br[j]);
        let z = sigmoid(xz[j] + gz[j] + bz[j]);
        let n = tanh(xn[j] + bin[j] + r * (gn[j] + bhn[j]));
        h_new[j] = (1.0 - z) * n + z * h_prev[j];
    }
}

/// The biases the gates add: `b_ih + b_hh` for `r` and `z`, and `b_in`, `b_hn` apart (`b_hn`
/// sits inside the reset product).
pub(crate) struct Biases {
    rz: Vec<f32>,
    x_n: Vec<f32>,
    h_n: Vec<f32>,
}

impl Biases {
    /// From `b_hh` `(3H)` and, when the input projection does not include it, `b_ih` `(3H)`.
    pub fn new(b_hh: &[f32], b_ih: Option<&[f32]>) -> Self {
        let hidden = b_hh.len() / 3;
        let zeros = vec![0f32; 3 * hidden];
        let b_ih = b_ih.unwrap_or(&zeros);
        Self {
            rz: (0..2 * hidden).map(|j| b_ih[j] + b_hh[j]).collect(),
            x_n: b_ih[2 * hidden..].to_vec(),
            h_n: b_hh[2 * hidden..].to_vec(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_functions_match_the_library() {
        let mut worst = [0f32; 3];
        for i in -20_000..=20_000 {
            let x = i as f32 * 0.001;
            let e = (fast_exp(x) - x.exp()).abs() / x.exp();
            let s = (sigmoid(x) - 1.0 / (1.0 + (-x).exp())).abs();
            let t = (tanh(x) - x.tanh()).abs();
            for (w, v) in worst.iter_mut().zip([e, s, t]) {
                *w = w.max(v);
            }
        }
        assert!(worst[0] < 3e-7, "exp relative error {}", worst[0]);
        assert!(worst[1] < 2e-7 && worst[2] < 2e-7, "{worst:?}");
        assert!(sigmoid(-200.0) < 1e-30);
        assert_eq!(tanh(100.0), 1.0);
        assert_eq!(tanh(-100.0), -1.0);
    }
}
