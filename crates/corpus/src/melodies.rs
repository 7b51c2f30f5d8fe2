//! Public-domain melodies encoded as études, for the demo clip and tests.

use crate::score::{Etude, Meter, ScoreNote};

/// One written note: (MIDI pitch, length in beats, slurred from the previous note).
type Written = (u8, f64, bool);

/// The first 16 bars of the Minuet in G major, BWV Anh. 114 (Christian Petzold, from the
/// Notebook for Anna Magdalena Bach, 1725; public domain), as a violinist would bow it:
/// eighth notes slurred in pairs, quarters détaché, a crescendo into bar 4 and a softer
/// answer from bar 9. 3/4 at 120 bpm: 24 s.
///
/// ```
/// let m = corpus::melodies::minuet_in_g();
/// assert_eq!(m.bars, 16);
/// assert_eq!(m.notes.len(), 64);
/// ```
pub fn minuet_in_g() -> Etude {
    const G4: u8 = 67;
    const A4: u8 = 69;
    const B4: u8 = 71;
    const C5: u8 = 72;
    const D5: u8 = 74;
    const E5: u8 = 76;
    const FS5: u8 = 78;
    const G5: u8 = 79;
    const FS4: u8 = 66;
    let q = |m: u8| (m, 1.0, false);
    let e = |m: u8, slurred: bool| (m, 0.5, slurred);
    let run = |a: u8, b: u8, c: u8, d: u8| [e(a, false), e(b, true), e(c, false), e(d, true)];
    let phrase_a: Vec<Vec<Written>> = vec![
        [vec![q(D5)], run(G4, A4, B4, C5).to_vec()].concat(),
        vec![q(D5), q(G4), q(G4)],
        [vec![q(E5)], run(C5, D5, E5, FS5).to_vec()].concat(),
        vec![q(G5), q(G4), q(G4)],
        [vec![q(C5)], run(D5, C5, B4, A4).to_vec()].concat(),
        [vec![q(B4)], run(C5, B4, A4, G4).to_vec()].concat(),
        [vec![q(FS4)], run(G4, A4, B4, G4).to_vec()].concat(),
        vec![(A4, 3.0, false)],
    ];
    let mut phrase_b = phrase_a.clone();
    phrase_b[6] = [vec![q(A4)], run(B4, A4, G4, FS4).to_vec()].concat();
    phrase_b[7] = vec![(G4, 3.0, false)];
    let bars: Vec<Vec<Written>> = phrase_a.into_iter().chain(phrase_b).collect();
    let mut notes = Vec::new();
    for (b, bar) in bars.iter().enumerate() {
        let mut beat = 3.0 * b as f64;
        // Dynamics: mf rising to f at bar 4, easing; the answer from bar 9 a little softer.
        let dynamic = match b {
            0..=3 => 0.55 + 0.08 * b as f32,
            4..=7 => 0.75 - 0.06 * (b - 4) as f32,
            8..=11 => 0.45 + 0.07 * (b - 8) as f32,
            _ => 0.6 - 0.07 * (b - 12) as f32,
        };
        for (i, (midi, len, slurred)) in bar.iter().enumerate() {
            notes.push(ScoreNote {
                start_beats: beat,
                dur_beats: *len,
                midi: *midi,
                slurred_from_previous: *slurred,
                dynamic,
                accent: i == 0 && b % 4 == 0,
            });
            beat += len;
        }
    }
    Etude {
        meter: Meter::ThreeFour,
        tempo_bpm: 120.0,
        tonic: 7,
        mode: "major".into(),
        bars: 16,
        notes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_add_up() {
        let m = minuet_in_g();
        let mut expected = 0.0;
        for n in &m.notes {
            assert!((n.start_beats - expected).abs() < 1e-9);
            expected += n.dur_beats;
        }
        assert!((expected - m.total_beats()).abs() < 1e-9);
    }
}
