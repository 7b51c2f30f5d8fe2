//! Synthetic room impulse responses, FFT convolution and the Schroeder RT60 measurement.
//!
//! A response is built from a shoebox room whose length is the drawn room size (width
//! 0.72 ×, height 0.3 × + 1.5 m, at most 12 m):
//! * the **direct sound** at index 0 (the propagation delay is removed, so the audio stays
//!   aligned with the labels) with amplitude 1;
//! * **early reflections**: the six first-order image sources of the walls, floor and
//!   ceiling, at their path-length differences (kept inside 3–40 ms) with amplitude
//!   `√(1 − α) · d / path`, α the mean absorption that Sabine's formula gives for the RT60;
//! * a **late tail** of Gaussian noise split into three bands (below 500 Hz, 500 Hz–4 kHz,
//!   above 4 kHz), each decaying exponentially — the low band 1.2 × and the high band
//!   0.5 × as long as the drawn RT60, which is the mid-band value (as ISO 3382 reports
//!   T_mid). Its energy relative to the direct sound is `(d / r_c)²`, `r_c = 0.057 √(V / RT60)`
//!   the critical distance, so a distant microphone hears more room.

use dsp_mel::fft::Planner;
use net_core::rng::Rng;

use crate::room::error::RoomError;

/// Speed of sound, m/s.
const SOUND_MPS: f64 = 343.0;

/// The geometry and decay of one channel's response.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct IrSpec {
    pub room_size_m: f64,
    pub rt60_s: f64,
    pub mic_distance_m: f64,
    pub mic_angle_rad: f64,
    pub mic_height_m: f64,
    /// Extra delay of the whole response, seconds (inter-channel time difference).
    pub delay_s: f64,
    /// Gain of the whole response, dB (inter-channel level difference).
    pub level_db: f64,
    /// Seed of the tail noise and the reflection jitter.
    pub seed: u64,
}

/// Room dimensions (length, width, height) in metres for a room size.
fn dimensions(size: f64) -> [f64; 3] {
    [size, 0.72 * size, (0.3 * size + 1.5).min(12.0)]
}

/// Critical distance in metres (direct and reverberant energy equal).
pub(crate) fn critical_distance_m(room_size_m: f64, rt60_s: f64) -> f64 {
    let [l, w, h] = dimensions(room_size_m.max(1.0));
    0.057 * (l * w * h / rt60_s.max(0.01)).sqrt()
}

/// One-pole low-pass coefficient for `hz` at `sr`.
fn one_pole(hz: f64, sr: f64) -> f64 {
    1.0 - (-std::f64::consts::TAU * hz.min(0.45 * sr) / sr).exp()
}

/// The impulse response of `spec` at `sr` Hz (RT60 0 gives a lone, possibly delayed and
/// scaled, impulse: dry).
pub(crate) fn impulse_response(spec: &IrSpec, sr: f64) -> Vec<f64> {
    let gain = 10f64.powf(spec.level_db / 20.0);
    let offset = (spec.delay_s.max(0.0) * sr).round() as usize;
    if spec.rt60_s <= 0.0 {
        let mut ir = vec![0.0; offset + 1];
        ir[offset] = gain;
        return ir;
    }
    let mut rng = Rng::new(spec.seed);
    let rt = spec.rt60_s;
    let [l, w, h] = dimensions(spec.room_size_m.max(1.0));
    let src = [0.25 * l, 0.5 * w, 1.4f64.min(0.8 * h)];
    let d = spec.mic_distance_m.max(0.05);
    let mic = [
        (src[0] + d * spec.mic_angle_rad.cos()).clamp(0.1, l - 0.1),
        (src[1] + d * spec.mic_angle_rad.sin()).clamp(0.1, w - 0.1),
        spec.mic_height_m.clamp(0.1, h - 0.1),
    ];
    let dist = |p: [f64; 3]| {
        ((p[0] - mic[0]).powi(2) + (p[1] - mic[1]).powi(2) + (p[2] - mic[2]).powi(2)).sqrt()
    };
    let direct = dist(src).max(0.05);
    let volume = l * w * h;
    let surface = 2.0 * (l * w + l * h + w * h);
    let alpha = (0.161 * volume / (surface * rt)).clamp(0.02, 0.95);
    let refl = (1.0 - alpha).sqrt();
    let tail_len = (1.2 * rt * 1.3 * sr) as usize + (0.05 * sr) as usize;
    let mut ir = vec![0.0; offset + tail_len.max(2)];
    ir[offset] = gain;
    // First-order images: mirror the source in each of the six boundaries.
    let mut first_tap = f64::INFINITY;
    for axis in 0..3 {
        let size = [l, w, h][axis];
        for wall in [0.0, size] {
            let mut img = src;
            img[axis] = 2.0 * wall - src[axis];
            let path = dist(img);
            let jitter = rng.uniform(-0.0005, 0.0005);
            let delay = ((path - direct) / SOUND_MPS + jitter).clamp(0.003, 0.040);
            first_tap = first_tap.min(delay);
            let i = offset + (delay * sr).round() as usize;
            if let Some(x) = ir.get_mut(i) {
                *x += gain * refl * direct / path;
            }
        }
    }
    // Late tail: three bands of one noise, each with its own decay, faded in after the
    // first reflection.
    let (a_lo, a_hi) = (one_pole(500.0, sr), one_pole(4_000.0, sr));
    let (mut lp_lo, mut lp_hi) = (0.0, 0.0);
    let k = -6.907_755_278_982_137 / sr; // ln(10⁻³) per sample
    let decay = [
        (k / (1.2 * rt)).exp(),
        (k / rt).exp(),
        (k / (0.5 * rt)).exp(),
    ];
    let mut env = [1.0f64; 3];
    let start = (first_tap * sr) as usize;
    let fade = (0.01 * sr).max(1.0);
    let mut tail = vec![0.0; tail_len];
    for (n, y) in tail.iter_mut().enumerate() {
        let x = rng.normal();
        lp_lo += a_lo * (x - lp_lo);
        lp_hi += a_hi * (x - lp_hi);
        let bands = [lp_lo, lp_hi - lp_lo, x - lp_hi];
        if n >= start {
            let ramp = ((n - start) as f64 / fade).min(1.0);
            *y = ramp * bands.iter().zip(&env).map(|(b, e)| b * e).sum::<f64>();
        }
        for (e, d) in env.iter_mut().zip(&decay) {
            *e *= d;
        }
    }
    let energy: f64 = tail.iter().map(|v| v * v).sum();
    let r_c = critical_distance_m(spec.room_size_m, rt);
    let target = (direct / r_c).powi(2) * gain * gain;
    let scale = if energy > 0.0 {
        (target / energy).sqrt()
    } else {
        0.0
    };
    for (y, t) in ir[offset..].iter_mut().zip(&tail) {
        *y += scale * t;
    }
    ir
}

/// `signal` convolved with `ir`, cut to `signal.len()` samples: overlap-add of FFT blocks
/// with one forward and one inverse plan reused for every block.
pub(crate) fn convolve(signal: &[f64], ir: &[f64]) -> Result<Vec<f64>, RoomError> {
    let n = signal.len();
    if n == 0 || ir.is_empty() {
        return Ok(vec![0.0; n]);
    }
    if ir.len() == 1 {
        return Ok(signal.iter().map(|x| x * ir[0]).collect());
    }
    let ir = &ir[..ir.len().min(n)];
    let fft_len = (2 * ir.len()).next_power_of_two().max(256);
    let block = fft_len + 1 - ir.len();
    let mut planner = Planner::<f64>::new();
    let forward = planner.real_forward(fft_len);
    let inverse = planner.real_inverse(fft_len);
    let mut time = vec![0.0; fft_len];
    time[..ir.len()].copy_from_slice(ir);
    let mut ir_spec = forward.make_output_vec();
    forward.process(&mut time, &mut ir_spec).map_err(fft_err)?;
    let mut spec = forward.make_output_vec();
    let mut out = vec![0.0; n];
    let norm = 1.0 / fft_len as f64;
    let mut start = 0;
    while start < n {
        let end = (start + block).min(n);
        time.fill(0.0);
        time[..end - start].copy_from_slice(&signal[start..end]);
        forward.process(&mut time, &mut spec).map_err(fft_err)?;
        for (s, h) in spec.iter_mut().zip(&ir_spec) {
            *s *= h;
        }
        // A product of real spectra is real at DC and Nyquist; drop the rounding residue.
        if let Some(first) = spec.first_mut() {
            first.im = 0.0;
        }
        if let Some(last) = spec.last_mut() {
            last.im = 0.0;
        }
        inverse.process(&mut spec, &mut time).map_err(fft_err)?;
        for (o, t) in out[start..].iter_mut().zip(&time) {
            *o += t * norm;
        }
        start = end;
    }
    Ok(out)
}

/// An FFT failure (buffers of the wrong length: a bug) as a [`RoomError`].
fn fft_err(e: impl std::fmt::Display) -> RoomError {
    RoomError::Convolution(e.to_string())
}

/// RT60 of an impulse response by Schroeder backward integration: the energy decay curve
/// is fitted by least squares between −5 and −25 dB (T20) and extrapolated to −60 dB.
/// `None` when the response never decays by 25 dB.
pub fn rt60_schroeder(ir: &[f64], sample_rate_hz: f64) -> Option<f64> {
    let mut edc = vec![0.0; ir.len()];
    let mut acc = 0.0;
    for (e, x) in edc.iter_mut().zip(ir).rev() {
        acc += x * x;
        *e = acc;
    }
    let total = *edc.first()?;
    if total <= 0.0 {
        return None;
    }
    let (mut n, mut st, mut sy, mut stt, mut sty) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (i, e) in edc.iter().enumerate() {
        let db = 10.0 * (e / total).log10();
        if (-25.0..=-5.0).contains(&db) {
            let t = i as f64 / sample_rate_hz;
            n += 1.0;
            st += t;
            sy += db;
            stt += t * t;
            sty += t * db;
        }
    }
    let denom = n * stt - st * st;
    if n < 2.0 || denom <= 0.0 {
        return None;
    }
    let slope = (n * sty - st * sy) / denom;
    (slope < 0.0).then(|| -60.0 / slope)
}
