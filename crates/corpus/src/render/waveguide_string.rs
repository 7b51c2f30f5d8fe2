//! The string of [`WaveguideViolin`](crate::render::WaveguideViolin): two fractional delay
//! lines meeting at the bow, a lossy bridge reflection and a friction law at the contact.
//!
//! Velocity waves travel from the bow to the nut and back (the *nut line*) and from the bow
//! to the bridge and back (the *bridge line*). Both ends reflect with inversion; the bridge
//! also loses energy through a one-pole low-pass (high partials die first). At the bow the
//! two incoming waves add up to the string's velocity there; the friction law decides how
//! much of the difference to the bow's velocity is forced into both outgoing waves:
//! everything while the hair sticks, a share falling with the slip speed once it slips.

/// A delay line read at a fractional delay by linear interpolation.
#[derive(Debug, Clone)]
pub(crate) struct FracDelay {
    buf: Vec<f64>,
    /// Index of the next write.
    pos: usize,
}

impl FracDelay {
    /// A line that can delay by up to `max_delay` samples.
    pub(crate) fn new(max_delay: usize) -> Self {
        Self {
            buf: vec![0.0; max_delay.max(4) + 2],
            pos: 0,
        }
    }

    /// The value written `delay` samples ago (1 ≤ delay ≤ capacity; clamped into that range).
    #[inline]
    pub(crate) fn read(&self, delay: f64) -> f64 {
        let n = self.buf.len();
        let d = delay.clamp(1.0, (n - 2) as f64);
        let whole = d as usize;
        let frac = d - whole as f64;
        let a = self.buf[(self.pos + n - whole) % n];
        let b = self.buf[(self.pos + n - whole - 1) % n];
        a + frac * (b - a)
    }

    /// Appends one sample.
    #[inline]
    pub(crate) fn write(&mut self, x: f64) {
        self.buf[self.pos] = x;
        self.pos += 1;
        if self.pos == self.buf.len() {
            self.pos = 0;
        }
    }
}

/// Share of the velocity difference the bow imposes on the string.
///
/// Below the sticking threshold `stick` (which grows with bow force) the hair drags the
/// string along (share 1); above it the string slips and the friction falls as the square
/// of `stick / |Δv|` — kinetic friction weaker than static friction and weaker still at
/// higher slip speed, the falling characteristic that sustains stick–slip motion.
#[inline]
pub(crate) fn friction_share(delta_v: f64, stick: f64) -> f64 {
    let a = delta_v.abs();
    if a <= stick {
        1.0
    } else {
        let r = stick / a;
        r * r
    }
}

/// Sticking threshold for a bow force 0..=1.
#[inline]
pub(crate) fn stick_threshold(force: f64) -> f64 {
    0.03 + 0.17 * force.clamp(0.0, 1.5)
}

/// Phase delay in samples of the bridge low-pass `(1 − a) / (1 − a z⁻¹)` at `omega` rad/sample.
pub(crate) fn lowpass_phase_delay(a: f64, omega: f64) -> f64 {
    if omega <= 0.0 {
        return a / (1.0 - a);
    }
    (a * omega.sin()).atan2(1.0 - a * omega.cos()) / omega
}

/// The bowed string's state.
#[derive(Debug, Clone)]
pub(crate) struct BowedString {
    nut: FracDelay,
    bridge: FracDelay,
    /// Bridge low-pass coefficient (0 = no high-frequency loss).
    lp_a: f64,
    lp_state: f64,
}

/// What the bow does during one sample.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BowInput {
    /// Loop period in samples (sample rate / f0).
    pub period: f64,
    /// Bow position as a fraction of the string length from the bridge.
    pub beta: f64,
    /// Bow velocity (signed: down- or up-bow).
    pub velocity: f64,
    /// Bow force 0..=1 (sets the sticking threshold).
    pub force: f64,
    /// The hair touches the string.
    pub on_string: bool,
    /// Loop gain per period (sets the free decay).
    pub loop_gain: f64,
}

impl BowedString {
    /// A silent string whose period may reach `max_period` samples.
    pub(crate) fn new(max_period: f64, lp_a: f64) -> Self {
        let cap = max_period.ceil().max(4.0) as usize + 4;
        Self {
            nut: FracDelay::new(cap),
            bridge: FracDelay::new(cap),
            lp_a: lp_a.clamp(0.0, 0.9),
            lp_state: 0.0,
        }
    }

    /// Advances one sample; returns the wave arriving at the bridge (its driving force).
    #[inline]
    pub(crate) fn tick(&mut self, bow: &BowInput) -> f64 {
        let omega = std::f64::consts::TAU / bow.period.max(2.0);
        let loop_delay = (bow.period - lowpass_phase_delay(self.lp_a, omega)).max(2.0);
        let d_bridge = (bow.beta * loop_delay).max(1.0);
        let d_nut = (loop_delay - d_bridge).max(1.0);
        // Loss per round trip spread over one reflection: the gain applies once per period.
        let g = bow.loop_gain;
        let at_bridge = self.bridge.read(d_bridge);
        self.lp_state = (1.0 - self.lp_a) * at_bridge + self.lp_a * self.lp_state;
        let from_bridge = -g * self.lp_state;
        let from_nut = -self.nut.read(d_nut);
        let string_v = from_bridge + from_nut;
        let injected = if bow.on_string {
            let dv = bow.velocity - string_v;
            dv * friction_share(dv, stick_threshold(bow.force))
        } else {
            0.0
        };
        self.nut.write(from_bridge + injected);
        self.bridge.write(from_nut + injected);
        at_bridge
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fractional_delay_interpolates() {
        let mut d = FracDelay::new(16);
        for i in 0..10 {
            d.write(f64::from(i));
        }
        // Last written 9 is 1 sample ago; 2.5 samples ago lies between 8 and 7.
        assert!((d.read(1.0) - 9.0).abs() < 1e-12);
        assert!((d.read(2.5) - 7.5).abs() < 1e-12);
    }

    #[test]
    fn friction_sticks_then_falls() {
        assert_eq!(friction_share(0.01, 0.1), 1.0);
        assert!(friction_share(0.2, 0.1) < 0.3);
        assert!(friction_share(-0.4, 0.1) < friction_share(-0.2, 0.1));
    }

    #[test]
    fn a_plucked_free_string_decays() {
        let mut s = BowedString::new(100.0, 0.3);
        let mut bow = BowInput {
            period: 100.0,
            beta: 0.1,
            velocity: 0.0,
            force: 0.0,
            on_string: false,
            loop_gain: 0.9,
        };
        s.bridge.write(1.0);
        let early: f64 = (0..1000).map(|_| s.tick(&bow).abs()).sum();
        bow.loop_gain = 0.9;
        let late: f64 = (0..1000).map(|_| s.tick(&bow).abs()).sum();
        assert!(early > 0.0 && late < early * 0.5, "{early} {late}");
    }
}
