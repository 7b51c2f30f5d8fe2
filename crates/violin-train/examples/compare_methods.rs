//! Method 1 (this crate's GRU) against Method 2 (motion-synth on a Performance) on the same
//! corpus clips, against the ground-truth motion, in one table.
//!
//! ```sh
//! cargo run --release -p violin-train --example compare_methods -- \
//!     --data /work/data/corpus-mix [--weighted W.safetensors] [--unweighted U.safetensors] \
//!     [--split test|val] [--json table.json]
//! ```
//!
//! Rows: the ground truth itself (Method 2 on the ground-truth Performance reproduces it —
//! checked, the line under the table gives the largest difference); Method 2 on a
//! Performance analysed from the audio (pitch-track notes, beat-track beats and downbeats,
//! bowing-net bow changes when its shipped weights load, else note onsets — the line under
//! the table says which; no arousal); Method 1 weighted (default: the shipped weights) and
//! unweighted (when given); the **direction-blind oracle**; and a static mean pose (the
//! training targets' mean) as the floor.
//!
//! The oracle bounds what any model trained with a squared error can do when the bow
//! direction cannot be told from the sound: it knows the ground-truth Performance (every
//! note, bow change, string, fingering, the body's sway, even each stroke's future length)
//! but not which way the bow goes, and outputs the mean of the two possible motions — the
//! ground truth and its mirror, bow position `p → 1 − p` (the bow planner is symmetric
//! under that mirror, so the mirror is exactly the motion of the opposite first direction).
//!
//! Columns (all on the 2-D pixel tracks, compared over the shorter length):
//! * `L1 px`: mean |error| per coordinate over all joints; `RW L1`: right wrist only;
//! * `jitter`: mean |acceleration| of the joints (px/frame²);
//! * `bone CV`: largest coefficient of variation of a bone's 2-D length;
//! * `attack F1`: bowing attacks (`pose_preproc::metrics::bowing_attack_frames`: sign changes
//!   of the right wrist's velocity along its main axis of motion after a zero-phase 5 Hz
//!   Butterworth low-pass, with a 0.05 px/frame hysteresis) against the ground-truth bow
//!   changes, ±3 frames (Kao & Su 2020);
//! * `beat align`: `motion_synth::metrics::beat_alignment` (speed minima vs beats, σ = 3).
//!
//! A second table gives the L1 of every joint.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::error::Error;
use std::path::{Path, PathBuf};
use std::time::Instant;

use dsp_mel::{load_audio, resample, Audio};
use gru_baseline::eval::l1_px;
use gru_baseline::GruBaseline;
use motion_synth::{synthesize, synthesize_detailed, PoseInput, SynthConfig};
use ndarray::Array3;
use performance::{Note, Performance};
use skeleton::formats::MotionFormat;
use skeleton::{Joint, Motion};
use violin_train::gru_data::corpus::read_manifest;

type Res<T> = Result<T, Box<dyn Error>>;

#[derive(Default, Clone)]
struct Row {
    name: String,
    clips: usize,
    frames: usize,
    l1: f64,
    rw_l1: f64,
    jitter: f64,
    bone_cv: f64,
    attack_f1: f64,
    beat_align: f64,
    beat_clips: usize,
    joint_l1: [f64; 10],
}

impl Row {
    fn add(
        &mut self,
        pred: &Motion,
        truth: &Motion,
        changes: &[usize],
        beats_s: &[f64],
    ) -> Res<()> {
        let n = pred.len().min(truth.len());
        let (p, t) = (cut(pred, n)?, cut(truth, n)?);
        self.clips += 1;
        self.frames += n;
        self.l1 += l1_px(&p, &t, None)? * n as f64;
        self.rw_l1 += l1_px(&p, &t, Some(Joint::RWrist))? * n as f64;
        for (acc, j) in self.joint_l1.iter_mut().zip(Joint::ALL) {
            *acc += l1_px(&p, &t, Some(j))? * n as f64;
        }
        self.jitter += f64::from(p.jitter());
        self.bone_cv += f64::from(p.max_bone_length_cv());
        let attacks = pose_preproc::metrics::bowing_attack_frames(&p)?;
        let changes: Vec<usize> = changes.iter().copied().filter(|&c| c < n).collect();
        self.attack_f1 += pose_preproc::metrics::match_events(&attacks, &changes, 3).f1;
        if let Some(b) = motion_synth::metrics::beat_alignment(&p, beats_s, 3.0) {
            self.beat_align += b;
            self.beat_clips += 1;
        }
        Ok(())
    }

    fn line(&self) -> String {
        let c = self.clips.max(1) as f64;
        let f = self.frames.max(1) as f64;
        format!(
            "| {:<34} | {:>6.1} | {:>6.1} | {:>6.2} | {:>7.3} | {:>9.3} | {:>10.3} |",
            self.name,
            self.l1 / f,
            self.rw_l1 / f,
            self.jitter / c,
            self.bone_cv / c,
            self.attack_f1 / c,
            self.beat_align / self.beat_clips.max(1) as f64
        )
    }

    fn joint_line(&self) -> String {
        let f = self.frames.max(1) as f64;
        let cells: Vec<String> = self
            .joint_l1
            .iter()
            .map(|v| format!("{:>5.1}", v / f))
            .collect();
        format!("| {:<34} | {} |", self.name, cells.join(" | "))
    }

    fn json(&self) -> serde_json::Value {
        let c = self.clips.max(1) as f64;
        let f = self.frames.max(1) as f64;
        let joints: serde_json::Map<String, serde_json::Value> = Joint::ALL
            .iter()
            .zip(&self.joint_l1)
            .map(|(j, v)| (j.name().to_string(), serde_json::json!(v / f)))
            .collect();
        serde_json::json!({
            "joint_l1_px": joints,
            "method": self.name, "clips": self.clips, "frames": self.frames,
            "l1_px": self.l1 / f, "right_wrist_l1_px": self.rw_l1 / f,
            "jitter_px_per_frame2": self.jitter / c, "max_bone_length_cv": self.bone_cv / c,
            "bowing_attack_f1_3": self.attack_f1 / c,
            "beat_alignment": self.beat_align / self.beat_clips.max(1) as f64,
        })
    }
}

/// The first `n` frames, 2-D only (every method is measured on its pixel track).
fn cut(m: &Motion, n: usize) -> Res<Motion> {
    let frames = m.frames().slice(ndarray::s![..n, .., ..]).to_owned();
    Ok(Motion::new(m.fps(), frames)?)
}

/// Method 2's input from the audio alone.
fn analysed_performance(
    audio: &Audio,
    detector: Option<&bowing_net::BowChangeDetector>,
) -> Res<Performance> {
    let a = resample(audio, 22_050)?;
    let track =
        pitch_track::PitchTracker::new(pitch_track::PitchConfig::default())?.track(a.samples())?;
    let notes = pitch_track::segment_notes(
        &track,
        a.samples(),
        22_050,
        &pitch_track::NoteConfig::default(),
    )?;
    let beats = beat_track::BeatTracker::new(beat_track::BeatConfig::default())?
        .track(a.samples(), Some(&notes))?;
    let duration = audio.duration_s();
    let table = fingering::OptimalPlanner::default();
    let played: Vec<Note> = notes
        .iter()
        .filter(|n| !table.table().places(n.midi).is_empty())
        .filter(|n| n.onset_s < duration)
        .map(|n| Note::new(n.onset_s, n.offset_s.min(duration), n.midi))
        .collect();
    let changes: Vec<f64> = match detector {
        Some(d) => d.detect_audio(audio)?,
        None => played.iter().skip(1).map(|n| n.onset_s).collect(),
    };
    let inside = |v: &[f64]| -> Vec<f64> {
        let mut out: Vec<f64> = v
            .iter()
            .copied()
            .filter(|t| (0.0..=duration).contains(t))
            .collect();
        out.dedup_by(|a, b| *a <= *b);
        out
    };
    Ok(Performance::builder(duration)
        .notes(played)
        .bow_changes(inside(&changes))
        .beats(inside(&beats.beats_s))
        .downbeats(inside(&beats.downbeats_s))
        .build()?)
}

/// The direction-blind oracle (see the module docs): the mean of the ground-truth synthesis
/// and its bow-mirrored twin, and the largest difference between that synthesis and `truth`.
fn direction_blind(perf: &Performance, truth: &Motion) -> Res<(Motion, f32)> {
    let cfg = SynthConfig::default();
    let syn = synthesize_detailed(perf, &cfg)?;
    let project = cfg.camera.projector();
    let real = syn.motion.frames();
    let n = real.dim().0;
    let mut mean = real.to_owned();
    for f in 0..n {
        let pose = cfg.rig.pose(&PoseInput {
            torso_pitch_rad: syn.body.torso_pitch_rad[f],
            head_pitch_rad: syn.body.head_pitch_rad[f],
            bow_position: 1.0 - f64::from(syn.bow.positions()[f]),
            string_index: syn.string_index[f],
            hand_semitones: syn.hand_semitones[f],
            hip_shift_m: syn.body.hip_shift_m[f],
            hip_roll_rad: syn.body.hip_roll_rad[f],
            right_flex: 0.0,
        });
        for (j, p) in pose.joints.iter().enumerate() {
            let xy = project(*p);
            for d in 0..2 {
                mean[[f, j, d]] = 0.5 * (real[[f, j, d]] + xy[d] as f32);
            }
        }
    }
    let m = n.min(truth.len());
    let check = (&real.slice(ndarray::s![..m, .., ..])
        - &truth.frames().slice(ndarray::s![..m, .., ..]))
        .mapv(f32::abs)
        .fold(0f32, |a, b| a.max(*b));
    Ok((Motion::new(30.0, mean)?, check))
}

fn mean_pose(root: &Path, items: &[PathBuf]) -> Res<Array3<f32>> {
    let mut sum = Array3::<f64>::zeros((1, 10, 2));
    let mut n = 0usize;
    for dir in items {
        let m = Motion::read(root.join(dir).join("motion.json"), MotionFormat::Json)?;
        for f in m.frames().outer_iter() {
            sum.index_axis_mut(ndarray::Axis(0), 0)
                .zip_mut_with(&f, |a, b| *a += f64::from(*b));
        }
        n += m.len();
    }
    Ok(sum.mapv(|v| (v / n.max(1) as f64) as f32))
}

fn main() -> Res<()> {
    let mut args = std::env::args().skip(1);
    let (mut data, mut weighted, mut unweighted, mut split, mut json) =
        (None, None, None, "test".to_string(), None);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--data" => data = args.next().map(PathBuf::from),
            "--weighted" => weighted = args.next().map(PathBuf::from),
            "--unweighted" => unweighted = args.next().map(PathBuf::from),
            "--split" => split = args.next().unwrap_or_default(),
            "--json" => json = args.next().map(PathBuf::from),
            other => return Err(format!("unknown argument {other}; see the example's docs").into()),
        }
    }
    let root = data.ok_or("--data DIR (a corpus) is required")?;
    let manifest = read_manifest(&root)?;
    let want = match split.as_str() {
        "test" => corpus::manifest::Split::Test,
        "val" => corpus::manifest::Split::Val,
        s => return Err(format!("--split {s}: expected test or val").into()),
    };
    let clips: Vec<PathBuf> = manifest
        .items
        .iter()
        .filter(|i| i.split == want)
        .map(|i| PathBuf::from(&i.dir))
        .collect();
    let train: Vec<PathBuf> = manifest
        .items
        .iter()
        .filter(|i| i.split == corpus::manifest::Split::Train)
        .map(|i| PathBuf::from(&i.dir))
        .collect();
    let net_w = match &weighted {
        Some(p) => GruBaseline::load(p)?,
        None => GruBaseline::pretrained()?,
    };
    let net_u = unweighted.as_ref().map(GruBaseline::load).transpose()?;
    let detector = bowing_net::BowChangeDetector::pretrained().ok();
    let still = mean_pose(&root, &train)?;

    let names = [
        "ground truth",
        "Method 2, analysed Performance",
        "Method 1 (GRU), weighted loss",
        "Method 1 (GRU), unweighted MSE",
        "direction-blind oracle",
        "static mean pose (floor)",
    ];
    let mut rows: Vec<Row> = names
        .iter()
        .map(|n| Row {
            name: n.to_string(),
            ..Row::default()
        })
        .collect();
    let (mut t_m1, mut t_analysis, mut audio_s, mut analysis_failures) = (0.0, 0.0, 0.0, 0);
    let mut worst_reproduction = 0f32;
    for dir in &clips {
        let item = root.join(dir);
        let audio = load_audio(item.join("audio.wav"))?;
        audio_s += audio.duration_s();
        let truth = Motion::read(item.join("motion.json"), MotionFormat::Json)?;
        let perf = Performance::read_json(item.join("performance.json"))?;
        let changes: Vec<usize> = perf
            .bow_changes_s()
            .iter()
            .map(|t| (t * 30.0).round() as usize)
            .collect();
        let beats = perf.beats_s().to_vec();
        rows[0].add(&truth, &truth, &changes, &beats)?;
        let (oracle, reproduced) = direction_blind(&perf, &truth)?;
        worst_reproduction = worst_reproduction.max(reproduced);
        let t = Instant::now();
        match analysed_performance(&audio, detector.as_ref())
            .and_then(|p| Ok(synthesize(&p, &SynthConfig::default())?))
        {
            Ok(m) => rows[1].add(&m, &truth, &changes, &beats)?,
            Err(e) => {
                eprintln!("{}: analysis failed: {e}", item.display());
                analysis_failures += 1;
            }
        }
        t_analysis += t.elapsed().as_secs_f64();
        let t = Instant::now();
        rows[2].add(&net_w.generate(&audio)?, &truth, &changes, &beats)?;
        t_m1 += t.elapsed().as_secs_f64();
        if let Some(net) = &net_u {
            rows[3].add(&net.generate(&audio)?, &truth, &changes, &beats)?;
        }
        rows[4].add(&oracle, &truth, &changes, &beats)?;
        let frames = Array3::from_shape_fn((truth.len(), 10, 2), |(_, j, d)| still[[0, j, d]]);
        rows[5].add(&Motion::new(30.0, frames)?, &truth, &changes, &beats)?;
    }
    println!(
        "{} split of {}: {} clips, {:.1} min\n",
        split,
        root.display(),
        clips.len(),
        audio_s / 60.0
    );
    println!("| method                             | L1 px  | RW L1  | jitter | bone CV | attack F1 | beat align |");
    println!("|------------------------------------|--------|--------|--------|---------|-----------|------------|");
    for r in rows.iter().filter(|r| r.clips > 0) {
        println!("{}", r.line());
    }
    println!("\nL1 per joint, px:\n");
    let header: Vec<&str> = Joint::ALL.iter().map(|j| j.name()).collect();
    println!("| {:<34} | {} |", "method", header.join(" | "));
    for r in rows.iter().filter(|r| r.clips > 0) {
        println!("{}", r.joint_line());
    }
    println!(
        "\nMethod 2 on the ground-truth Performance reproduces the ground truth within {worst_reproduction:.4} px."
    );
    println!(
        "Method 2 analysed: notes pitch-track, beats/downbeats beat-track, bow changes {}, no arousal{}.",
        if detector.is_some() { "bowing-net (shipped weights)" } else { "= note onsets (bowing-net weights not available)" },
        if analysis_failures > 0 { format!(", {analysis_failures} clips failed") } else { String::new() }
    );
    println!(
        "Method 1 weights: {}; inference {:.2} s for {:.0} s of audio (incl. mel); analysis + synthesis {:.2} s.",
        weighted.as_ref().map_or("shipped".to_string(), |p| p.display().to_string()),
        t_m1,
        audio_s,
        t_analysis
    );
    if let Some(path) = json {
        let v: Vec<_> = rows.iter().filter(|r| r.clips > 0).map(Row::json).collect();
        atomic_file::write_bytes_atomically(&path, serde_json::to_string_pretty(&v)?.as_bytes())?;
    }
    Ok(())
}
