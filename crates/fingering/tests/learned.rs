//! The learned planner: playable, deterministic plans; the style knobs do what they say.

use fingering::{
    learned_places, FingeringPlanner, FingeringStyle, LearnedParams, LearnedPlanner,
    OptimalPlanner, ViolinString,
};

/// A two-octave D major scale up and down, D4..D6..D4.
fn d_major() -> Vec<u8> {
    let steps = [2, 2, 1, 2, 2, 2, 1];
    let mut up = vec![62u8];
    for k in 0..14 {
        let last = up[up.len() - 1];
        up.push(last + steps[k % 7]);
    }
    let mut all = up.clone();
    all.extend(up.iter().rev().skip(1));
    all
}

#[test]
fn plans_play_every_pitch_and_are_deterministic() {
    let planner = LearnedPlanner::default();
    let mut notes: Vec<u8> = d_major();
    // A pseudo-random walk over the whole range.
    let mut x = 7u32;
    for _ in 0..300 {
        x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
        notes.push(55 + ((x >> 16) % 51) as u8);
    }
    let plan = planner.plan(&notes).unwrap();
    assert_eq!(plan.len(), notes.len());
    for (f, &m) in plan.iter().zip(&notes) {
        assert_eq!(f.midi(), m, "{f:?}");
        assert!(learned_places(m).contains(f));
    }
    assert_eq!(planner.plan(&notes).unwrap(), plan);
    assert!(planner.plan(&[]).unwrap().is_empty());
    let err = planner.plan(&[60, 40]).unwrap_err();
    assert!(err.to_string().contains("note 1"), "{err}");
}

#[test]
fn a_scale_in_first_position_uses_open_strings_like_a_violinist() {
    // G major G3..G4 in first position is the first thing violinists learn.
    let plan = LearnedPlanner::default()
        .plan(&[55, 57, 59, 60, 62, 64, 66, 67])
        .unwrap();
    assert!(plan.iter().all(|f| f.position <= 1), "{plan:?}");
    assert!(plan[0].is_open() && plan[4].is_open(), "{plan:?}");
}

#[test]
fn style_knobs_change_the_plan_the_way_they_say() {
    let notes = d_major();
    let count_open = |p: &[fingering::Fingering]| p.iter().filter(|f| f.is_open()).count();
    let mean_position = |p: &[fingering::Fingering]| {
        p.iter().map(|f| f64::from(f.position)).sum::<f64>() / p.len() as f64
    };
    let base = LearnedPlanner::default().plan(&notes).unwrap();
    let avoid = LearnedPlanner::default()
        .with_style(FingeringStyle::avoid_open_strings())
        .plan(&notes)
        .unwrap();
    let prefer = LearnedPlanner::default()
        .with_style(FingeringStyle::prefer_open_strings())
        .plan(&notes)
        .unwrap();
    assert_eq!(count_open(&avoid), 0, "{avoid:?}");
    assert!(count_open(&prefer) >= count_open(&base));
    let low = LearnedPlanner::default()
        .with_style(FingeringStyle::low_positions())
        .plan(&notes)
        .unwrap();
    let high = LearnedPlanner::default()
        .with_style(FingeringStyle::high_positions())
        .plan(&notes)
        .unwrap();
    assert!(mean_position(&low) <= mean_position(&base));
    assert!(mean_position(&high) > mean_position(&base));
    // Sul G for the first octave: every note the G string can play stays on it.
    let sul = LearnedPlanner::default()
        .with_style(FingeringStyle::default().sul(ViolinString::G, 0..8))
        .plan(&notes)
        .unwrap();
    assert!(
        sul[..8].iter().all(|f| f.string == ViolinString::G),
        "{sul:?}"
    );
    // The optimal planner takes the same knobs.
    let optimal = OptimalPlanner::default()
        .with_style(FingeringStyle::default().sul(ViolinString::D, 0..14))
        .plan(&notes)
        .unwrap();
    assert!(optimal[..14].iter().all(|f| f.string == ViolinString::D));
    let optimal_avoid = OptimalPlanner::default()
        .with_style(FingeringStyle::avoid_open_strings())
        .plan(&notes)
        .unwrap();
    assert_eq!(count_open(&optimal_avoid), 0);
}

#[test]
fn shipped_parameters_name_their_source_and_pieces() {
    let p = LearnedParams::shipped().unwrap();
    let text = p.notes.join(" ");
    assert!(text.contains("Chen et al., IUI 2021"));
    assert!(text.contains("Tsung-Ping/Violin-Fingering-Generation"));
    for reserved in ["bach1", "bach2", "flower", "mend1"] {
        assert!(
            !text.contains(reserved),
            "{reserved} must not be used for training"
        );
    }
}

#[test]
fn ten_thousand_notes_plan_quickly() {
    let notes: Vec<u8> = (0..10_000).map(|i| 60 + ((i * 7) % 30) as u8).collect();
    let t = std::time::Instant::now();
    let plan = LearnedPlanner::default().plan(&notes).unwrap();
    assert_eq!(plan.len(), notes.len());
    // Generous for debug builds on a shared machine; release takes a few ms per 1000 notes.
    assert!(t.elapsed().as_secs_f64() < 30.0);
}

#[test]
fn the_span_context_counts_only_when_it_weighs() {
    let shipped = LearnedParams::shipped().unwrap();
    let span = shipped
        .span
        .expect("the shipped parameters carry a span context");
    assert!(span.weight > 0.0 && !shipped.span_emission.is_empty());
    let without = LearnedParams {
        span: None,
        ..shipped.clone()
    };
    let weightless = LearnedParams {
        span: Some(fingering::SpanContext {
            weight: 0.0,
            ..span
        }),
        ..shipped.clone()
    };
    // A melody that climbs and falls through the registers.
    let melody: Vec<u8> = (0..400)
        .map(|i| 62 + ((i * 5 + (i / 7) * 3) % 29) as u8)
        .collect();
    let plan = |p: &LearnedParams| LearnedPlanner::new(p).plan(&melody).unwrap();
    assert_eq!(plan(&without), plan(&weightless));
    let with = plan(&shipped);
    assert!(with.iter().zip(&melody).all(|(f, &m)| f.midi() == m));
    assert_ne!(with, plan(&without), "the span context changes nothing");
}
