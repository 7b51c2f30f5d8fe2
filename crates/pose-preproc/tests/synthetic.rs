//! The whole pipeline on synthetic OpenPose directories with known ground truth.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{detectable, generate, write_openpose_dir, SynthConfig};
use pose_preproc::metrics::match_events;
use pose_preproc::{bow_change_labels, preprocess_dir, ChangePoint, PreprocConfig};
use skeleton::{Joint, PoseLayout, JOINT_COUNT};

const FRAMES: usize = 900; // 30 s per clip
const CLIPS: usize = 8;

#[test]
fn bow_change_labels_reach_f1_095_at_2_frames_in_both_layouts() {
    let dir = tempfile::tempdir().unwrap();
    // (tp, fp, fn): extremum, run centre, extremum on the clean ground-truth track.
    let mut totals = [(0usize, 0usize, 0usize); 3];
    for i in 0..CLIPS {
        let layout = if i % 2 == 0 {
            PoseLayout::Body25
        } else {
            PoseLayout::Coco18
        };
        let clip = generate(&SynthConfig::standard(FRAMES, layout, 100 + i as u64));
        let path = dir.path().join(format!("clip{i}"));
        write_openpose_dir(&path, &clip, "clip");
        let truth = detectable(&clip.bow_changes, FRAMES);
        // The rule's own limit: labels of the clean, jitter-free ground-truth wrist.
        let clean = skeleton::Motion::new(30.0, clip.truth.clone()).unwrap();
        let on_truth = match_events(&bow_change_labels(&clean, &Default::default()), &truth, 2);
        totals[2].0 += on_truth.true_positives;
        totals[2].1 += on_truth.false_positives;
        totals[2].2 += on_truth.false_negatives;
        for (m, mode) in [ChangePoint::Extremum, ChangePoint::RunCentre]
            .into_iter()
            .enumerate()
        {
            let mut cfg = PreprocConfig::default();
            cfg.labels.change_point = mode;
            let track = preprocess_dir(&path, &cfg).unwrap();
            assert_eq!(track.quality.layout, layout);
            let found = match_events(&track.bow_change_frames, &truth, 2);
            println!(
                "clip {i} ({layout:?}, {mode:?}): {} changes, P {:.3} R {:.3} F1 {:.3}",
                truth.len(),
                found.precision,
                found.recall,
                found.f1
            );
            if mode == ChangePoint::Extremum {
                assert!(found.f1 >= 0.85, "clip {i}: F1 {:.3}", found.f1);
            }
            totals[m].0 += found.true_positives;
            totals[m].1 += found.false_positives;
            totals[m].2 += found.false_negatives;
        }
    }
    let f1 = |(tp, fp, fn_): (usize, usize, usize)| 2.0 * tp as f64 / (2 * tp + fp + fn_) as f64;
    println!(
        "pooled F1 at ±2 frames: extremum {:.3}, run centre {:.3}, extremum on clean truth {:.3} (tp, fp, fn = {:?} / {:?} / {:?})",
        f1(totals[0]),
        f1(totals[1]),
        f1(totals[2]),
        totals[0],
        totals[1],
        totals[2]
    );
    assert!(f1(totals[0]) >= 0.95, "pooled F1 {:.3}", f1(totals[0]));
}

#[test]
fn performer_is_never_swapped_for_the_bystander_or_a_false_detection() {
    let dir = tempfile::tempdir().unwrap();
    for (i, layout) in [PoseLayout::Body25, PoseLayout::Coco18]
        .into_iter()
        .enumerate()
    {
        let mut synth = SynthConfig::standard(600, layout, 7 + i as u64);
        synth.false_detections_per_100_frames = 2.0;
        let clip = generate(&synth);
        assert!(clip.bystander_frames > 0 && clip.false_detection_frames.len() >= 6);
        let path = dir.path().join(format!("p{i}"));
        write_openpose_dir(&path, &clip, "take");
        let cfg = PreprocConfig {
            center: false,
            ..Default::default()
        };
        let track = preprocess_dir(&path, &cfg).unwrap();
        let m = track.motion.frames();
        for t in 0..600 {
            let mut d: Vec<f32> = (0..JOINT_COUNT)
                .map(|j| {
                    (m[[t, j, 0]] - clip.truth[[t, j, 0]])
                        .hypot(m[[t, j, 1]] - clip.truth[[t, j, 1]])
                })
                .collect();
            d.sort_by(f32::total_cmp);
            assert!(
                d[JOINT_COUNT / 2] < 15.0,
                "{layout:?} frame {t}: median joint error {} px",
                d[5]
            );
        }
        let q = &track.quality;
        assert_eq!(
            q.frames_without_performer,
            clip.absent_frames.len(),
            "{q:?}"
        );
        assert_eq!(q.performer_reacquisitions, 0);
        // Every false detection out-scores the performer: each is a rejected switch.
        assert!(
            q.performer_switches_rejected >= clip.false_detection_frames.len(),
            "{q:?}"
        );
        assert!(q.frames_with_other_people >= clip.bystander_frames);
    }
}

#[test]
fn output_is_centred_smoothed_and_finite() {
    let dir = tempfile::tempdir().unwrap();
    let clip = generate(&SynthConfig::standard(300, PoseLayout::Body25, 3));
    write_openpose_dir(dir.path(), &clip, "c");
    let track = preprocess_dir(dir.path(), &PreprocConfig::default()).unwrap();
    let unsmoothed = PreprocConfig {
        median_window: 1,
        ..Default::default()
    };
    let raw = preprocess_dir(dir.path(), &unsmoothed).unwrap();
    let m = &track.motion;
    assert_eq!(m.len(), 300);
    assert_eq!(m.fps(), 30.0);
    assert!(m.frames().iter().all(|v| v.is_finite()));
    let (mx, my) = m.mean_xy();
    // Centred before the median filter, which moves the mean by a fraction of a pixel.
    assert!(mx.abs() < 1.0 && my.abs() < 1.0, "mean ({mx}, {my})");
    let [ox, oy] = track.quality.center_offset_px;
    assert!(
        (ox - 640.0).abs() < 40.0 && (oy - 300.0).abs() < 40.0,
        "offset ({ox}, {oy})"
    );
    // The median filter removes much of the 3 px jitter of the (nearly still) neck.
    let neck = Joint::Neck.index();
    let smoothed = skeleton::metrics::jitter_per_joint(m.frames())[neck];
    let unsmoothed = skeleton::metrics::jitter_per_joint(raw.motion.frames())[neck];
    assert!(
        smoothed < 0.6 * unsmoothed,
        "neck jitter {smoothed} vs {unsmoothed} unsmoothed"
    );
}

#[test]
fn long_dropout_is_held_and_reported() {
    let dir = tempfile::tempdir().unwrap();
    let mut synth = SynthConfig::standard(300, PoseLayout::Coco18, 11);
    synth.dropouts_per_100_frames = 0.0;
    synth.absences_per_100_frames = 0.0;
    synth.long_dropout = Some((Joint::LWrist, 100, 40));
    let clip = generate(&synth);
    write_openpose_dir(dir.path(), &clip, "long");
    let cfg = PreprocConfig {
        center: false,
        median_window: 1,
        ..Default::default()
    };
    let track = preprocess_dir(dir.path(), &cfg).unwrap();
    let q = &track.quality;
    println!("{}", serde_json::to_string_pretty(q).unwrap());
    assert_eq!(q.long_gaps.len(), 1, "{q:?}");
    let gap = q.long_gaps[0];
    assert_eq!(
        (gap.joint, gap.start_frame, gap.len),
        (Joint::LWrist, 100, 40)
    );
    assert_eq!(q.held_joint_frames, 40);
    assert_eq!(q.filled_joint_frames, 0);
    // Held at the last valid value: frames 100..140 equal frame 99.
    let w = track.motion.joint(Joint::LWrist);
    for t in 100..140 {
        assert_eq!(w.row(t), w.row(99));
    }
    assert_ne!(w.row(140), w.row(99));
    let json = serde_json::to_value(q).unwrap();
    assert_eq!(
        json["long_gaps"][0],
        serde_json::json!({"joint": "l_wrist", "start_frame": 100, "len": 40})
    );
    assert_eq!(json["layout"], "Coco18");
}

#[test]
fn short_dropouts_are_interpolated_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let mut synth = SynthConfig::standard(400, PoseLayout::Body25, 5);
    synth.bystander = false;
    synth.false_detections_per_100_frames = 0.0;
    synth.absences_per_100_frames = 0.0;
    synth.dropouts_per_100_frames = 3.0;
    let clip = generate(&synth);
    write_openpose_dir(dir.path(), &clip, "s");
    let track = preprocess_dir(dir.path(), &PreprocConfig::default()).unwrap();
    let q = &track.quality;
    assert!(q.filled_joint_frames > 0, "{q:?}");
    assert!(q.long_gaps.is_empty(), "{q:?}");
    assert_eq!(
        (q.frames_without_performer, q.frames_with_other_people),
        (0, 0)
    );
}
