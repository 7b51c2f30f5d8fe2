//! What a preview draws of the whole performer beyond the ten core joints: legs, feet,
//! eyes and ears, both hands' finger chains, the violin's strings and the bow hair.
//!
//! Points are numbered across the performer's parts in [`PerformerPart::ALL`] order (body
//! 0–24, left hand 25–45, right hand 46–66, instrument 67–83), so the GIF painter and the
//! HTML player share one list of segments.

use skeleton::{
    BodyPoint, InstrumentPart, Joint, Motion, PerformerPart, BODY25_BONES, BONES, HAND_BONES,
};

/// Ink of a segment (the names match the player's colours).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ink {
    /// Trunk and legs.
    Trunk,
    /// Right (bow) hand.
    Right,
    /// Left hand.
    Left,
    /// Head (eyes, ears).
    Head,
    /// Strings.
    ViolinDark,
    /// Bow hair.
    Bow,
}

impl Ink {
    /// The player's colour key (`INK.<key>` in `player.html`).
    pub fn key(self) -> &'static str {
        match self {
            Ink::Trunk => "trunk",
            Ink::Right => "right",
            Ink::Left => "left",
            Ink::Head => "head",
            Ink::ViolinDark => "violinDark",
            Ink::Bow => "bow",
        }
    }
}

/// Offset of `part`'s first point in the concatenated numbering.
pub fn part_offset(part: PerformerPart) -> usize {
    PerformerPart::ALL
        .iter()
        .take_while(|p| **p != part)
        .map(|p| p.point_count())
        .sum()
}

/// The segments `(a, b, ink, width relative to a bone)` drawn for a performer.
pub fn performer_segments() -> Vec<(usize, usize, Ink, f32)> {
    let core = |p: BodyPoint| Joint::ALL.iter().any(|j| BodyPoint::of_joint(*j) == p);
    let in_core = |a: BodyPoint, b: BodyPoint| {
        core(a)
            && core(b)
            && BONES.iter().any(|(x, y)| {
                let (x, y) = (BodyPoint::of_joint(*x), BodyPoint::of_joint(*y));
                (x, y) == (a, b) || (y, x) == (a, b)
            })
    };
    let mut out = Vec::with_capacity(64);
    for (a, b) in BODY25_BONES {
        if in_core(a, b) {
            continue;
        }
        let ink = if [a, b].iter().any(|p| {
            matches!(
                p,
                BodyPoint::REye | BodyPoint::LEye | BodyPoint::REar | BodyPoint::LEar
            )
        }) {
            Ink::Head
        } else {
            Ink::Trunk
        };
        out.push((a.index(), b.index(), ink, 1.2));
    }
    for (part, ink) in [
        (PerformerPart::LeftHand, Ink::Left),
        (PerformerPart::RightHand, Ink::Right),
    ] {
        let o = part_offset(part);
        for (a, b) in HAND_BONES {
            out.push((o + a, o + b, ink, 0.5));
        }
    }
    let o = part_offset(PerformerPart::Instrument);
    for s in 0..4 {
        let (a, b) = (
            InstrumentPart::StringAtNut(s),
            InstrumentPart::StringAtBridge(s),
        );
        out.push((o + a.index(), o + b.index(), Ink::ViolinDark, 0.25));
    }
    let (a, b) = (InstrumentPart::BowHairFrog, InstrumentPart::BowHairTip);
    out.push((o + a.index(), o + b.index(), Ink::Bow, 0.35));
    out
}

/// The performer's 2-D point `k` (concatenated numbering) at frame `f`, when finite.
pub fn performer_point(motion: &Motion, f: usize, k: usize) -> Option<(f32, f32)> {
    let p = motion.performer()?;
    let mut k = k;
    for part in PerformerPart::ALL {
        let n = part.point_count();
        if k < n {
            let t = p.track(part);
            let (x, y) = (t[[f, k, 0]], t[[f, k, 1]]);
            return (x.is_finite() && y.is_finite()).then_some((x, y));
        }
        k -= n;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_cover_legs_hands_strings_and_hair_within_range() {
        let segs = performer_segments();
        let total: usize = PerformerPart::ALL.iter().map(|p| p.point_count()).sum();
        assert!(segs.iter().all(|&(a, b, _, _)| a < total && b < total));
        assert_eq!(segs.iter().filter(|s| s.2 == Ink::Left).count(), 20);
        assert!(segs
            .iter()
            .any(|s| s.0 == BodyPoint::RHip.index() && s.1 == BodyPoint::RKnee.index()));
        assert_eq!(part_offset(PerformerPart::Instrument), 67);
    }
}
