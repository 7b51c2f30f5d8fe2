//! Experiment: can a note-level network with a wide melodic context (a temporal convolution
//! over the notes, ±62 notes) learn where violinists put the hand better than the counted
//! model? Leave-one-piece-out over the ten TNUA training pieces only (the reserved pieces are
//! never read).
//!
//! ```text
//! cargo run --release -p violin-train --example fingering_tcn -- TNUA_DIR [EPOCHS]
//! ```

use std::path::PathBuf;

use candle_core::{DType, Device, Tensor, D};
use candle_nn::{Linear, Module, VarBuilder, VarMap};
use fingering::train::{agreement, read_tnua_dir, Agreement, Label, Piece, RESERVED_PIECES};
use fingering::{learned_places, Fingering, ViolinString};
use net_core::nn::{DropoutRng, Tcn, TcnConfig};
use net_core::rng::Rng;
use net_core::{Adam, AdamConfig};

const PITCHES: usize = 51; // MIDI 55..=105
const IV: usize = 28; // -13..=13 and "none"
const F: usize = PITCHES + 2 * IV;
const POSITIONS: usize = 12;
const CROP: usize = 128;
const BATCH: usize = 32;

fn features(midi: &[u8]) -> Vec<f32> {
    let mut x = vec![0.0f32; midi.len() * F];
    let iv = |a: u8, b: u8| ((i16::from(b) - i16::from(a)).clamp(-13, 13) + 13) as usize;
    for (i, &m) in midi.iter().enumerate() {
        let row = &mut x[i * F..(i + 1) * F];
        row[usize::from(m.saturating_sub(55)).min(PITCHES - 1)] = 1.0;
        let prev = i.checked_sub(1).map_or(IV - 1, |j| iv(midi[j], m));
        let next = midi.get(i + 1).map_or(IV - 1, |&n| iv(m, n));
        row[PITCHES + prev] = 1.0;
        row[PITCHES + IV + next] = 1.0;
    }
    x
}

struct Sequence {
    x: Vec<f32>,
    string: Vec<u32>,
    string_w: Vec<f32>,
    position: Vec<u32>,
    position_w: Vec<f32>,
}

fn sequence(seq: &[(u8, Label)]) -> Sequence {
    let midi: Vec<u8> = seq.iter().map(|s| s.0).collect();
    let mut s = Sequence {
        x: features(&midi),
        string: Vec::new(),
        string_w: Vec::new(),
        position: Vec::new(),
        position_w: Vec::new(),
    };
    for (_, l) in seq {
        let ok = (1..=4).contains(&l.string);
        s.string.push(u32::from(l.string.clamp(1, 4) - 1));
        s.string_w.push(f32::from(u8::from(ok)));
        let pos_ok = ok && l.finger != 0 && l.position >= 1;
        s.position
            .push(u32::from(l.position.clamp(1, POSITIONS as u8) - 1));
        s.position_w.push(f32::from(u8::from(pos_ok)));
    }
    s
}

struct Net {
    tcn: Tcn,
    string: Linear,
    position: Linear,
}

impl Net {
    fn new(vb: VarBuilder, rng: DropoutRng, channels: usize) -> candle_core::Result<Net> {
        let cfg = TcnConfig {
            in_features: F,
            channels,
            dilations: vec![1, 2, 4, 8, 16, 1, 2, 4, 8, 16],
            dropout: 0.2,
        };
        Ok(Net {
            tcn: Tcn::new(&cfg, vb.pp("tcn"), rng)?,
            string: candle_nn::linear(channels, 4, vb.pp("string"))?,
            position: candle_nn::linear(channels, POSITIONS, vb.pp("position"))?,
        })
    }

    fn forward_t(&self, x: &Tensor, train: bool) -> candle_core::Result<(Tensor, Tensor)> {
        let h = self.tcn.forward_t(x, train)?.relu()?;
        Ok((self.string.forward(&h)?, self.position.forward(&h)?))
    }
}

fn masked_ce(logits: &Tensor, y: &[u32], w: &[f32]) -> candle_core::Result<Tensor> {
    let n = y.len();
    let log_p = candle_nn::ops::log_softmax(&logits.reshape((n, ()))?, D::Minus1)?;
    let yt = Tensor::from_vec(y.to_vec(), (n, 1), &Device::Cpu)?;
    let picked = log_p.gather(&yt, 1)?.squeeze(1)?;
    let wt = Tensor::from_vec(w.to_vec(), n, &Device::Cpu)?;
    let total: f32 = w.iter().sum::<f32>().max(1.0);
    (picked * wt)?.sum_all()? * (-1.0 / f64::from(total))
}

fn train(
    seqs: &[Sequence],
    epochs: usize,
    seed: u64,
    channels: usize,
) -> Result<Net, Box<dyn std::error::Error>> {
    let varmap = VarMap::new();
    let net = Net::new(
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
        DropoutRng::new(seed ^ 7),
        channels,
    )?;
    net_core::vars::init_seeded(&varmap, seed, |name, dims| {
        name.ends_with("weight")
            .then(|| (6.0 / (dims.iter().sum::<usize>() as f64)).sqrt())
    })?;
    let mut adam = Adam::new(
        net_core::vars::trainable_vars(&varmap, |_| false),
        AdamConfig {
            learning_rate: 2e-3,
            ..AdamConfig::default()
        },
    )?;
    let total: usize = seqs.iter().map(|s| s.string.len()).sum();
    let weights: Vec<f64> = seqs.iter().map(|s| s.string.len() as f64).collect();
    let steps = total.div_ceil(BATCH * CROP).max(1);
    let mut rng = Rng::new(seed);
    for epoch in 0..epochs {
        adam.config.learning_rate = 2e-3 * (1.0 - epoch as f64 / epochs as f64).max(0.05);
        for _ in 0..steps {
            let n = BATCH * CROP;
            let mut x = vec![0.0f32; n * F];
            let (mut ys, mut ws, mut yp, mut wp) = (
                vec![0u32; n],
                vec![0.0f32; n],
                vec![0u32; n],
                vec![0.0f32; n],
            );
            for b in 0..BATCH {
                let s = &seqs[rng.weighted(&weights).unwrap_or(0)];
                let len = s.string.len();
                let start = if len > CROP {
                    rng.int(0, (len - CROP) as i64) as usize
                } else {
                    0
                };
                let take = (len - start).min(CROP);
                let o = b * CROP;
                x[o * F..(o + take) * F].copy_from_slice(&s.x[start * F..(start + take) * F]);
                ys[o..o + take].copy_from_slice(&s.string[start..start + take]);
                ws[o..o + take].copy_from_slice(&s.string_w[start..start + take]);
                yp[o..o + take].copy_from_slice(&s.position[start..start + take]);
                wp[o..o + take].copy_from_slice(&s.position_w[start..start + take]);
            }
            let xt = Tensor::from_vec(x, (BATCH, CROP, F), &Device::Cpu)?;
            let (ls, lp) = net.forward_t(&xt, true)?;
            let loss = (masked_ce(&ls, &ys, &ws)? + masked_ce(&lp, &yp, &wp)?)?;
            adam.backward_step(&loss)?;
        }
    }
    Ok(net)
}

/// Per-note log-probabilities, one row per note.
type LogProbs = Vec<Vec<f32>>;

/// Per note: log p(string) (4) and log p(position) (12).
fn predict(net: &Net, midi: &[u8]) -> candle_core::Result<(LogProbs, LogProbs)> {
    let n = midi.len();
    let xt = Tensor::from_vec(features(midi), (1, n, F), &Device::Cpu)?;
    let (ls, lp) = net.forward_t(&xt, false)?;
    let ls = candle_nn::ops::log_softmax(&ls.squeeze(0)?, D::Minus1)?.to_vec2::<f32>()?;
    let lp = candle_nn::ops::log_softmax(&lp.squeeze(0)?, D::Minus1)?.to_vec2::<f32>()?;
    Ok((ls, lp))
}

/// Viterbi over the learned planner's places: cost = −log p(string) − log p(position)
/// (stopped notes) + `shift` per position change between stopped notes.
fn decode(midi: &[u8], ls: &[Vec<f32>], lp: &[Vec<f32>], shift: f32) -> Vec<Fingering> {
    let places: Vec<Vec<Fingering>> = midi.iter().map(|&m| learned_places(m)).collect();
    let own = |i: usize, f: &Fingering| -> f32 {
        let s = -ls[i][usize::from(f.string.number() - 1)];
        if f.is_open() {
            s
        } else {
            s - lp[i][usize::from(f.position.clamp(1, POSITIONS as u8) - 1)]
        }
    };
    let mut score: Vec<f32> = places[0].iter().map(|f| own(0, f)).collect();
    let mut back: Vec<Vec<usize>> = vec![vec![0; places[0].len()]];
    for i in 1..midi.len() {
        let mut next = Vec::with_capacity(places[i].len());
        let mut from = Vec::with_capacity(places[i].len());
        for f in &places[i] {
            let (mut best, mut arg) = (f32::INFINITY, 0);
            for (j, p) in places[i - 1].iter().enumerate() {
                let moved = !f.is_open() && !p.is_open() && f.position != p.position;
                let c = score[j] + if moved { shift } else { 0.0 };
                if c < best {
                    (best, arg) = (c, j);
                }
            }
            next.push(best + own(i, f));
            from.push(arg);
        }
        score = next;
        back.push(from);
    }
    let mut j = (0..score.len())
        .min_by(|&a, &b| score[a].total_cmp(&score[b]))
        .unwrap_or(0);
    let mut plan = vec![Fingering::open(ViolinString::G, 1); midi.len()];
    for i in (0..midi.len()).rev() {
        plan[i] = places[i][j];
        j = back[i][j];
    }
    plan
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = PathBuf::from(
        args.first()
            .ok_or("usage: fingering_tcn TNUA_DIR [EPOCHS] [CHANNELS]")?,
    );
    let epochs: usize = args.get(1).map_or(Ok(30), |v| v.parse())?;
    let channels: usize = args.get(2).map_or(Ok(64), |v| v.parse())?;
    let pieces = read_tnua_dir(&dir)?;
    let train_pieces: Vec<&Piece> = pieces
        .iter()
        .filter(|p| !RESERVED_PIECES.contains(&p.name.as_str()))
        .collect();
    let shifts = [0.0f32, 0.5, 1.0, 2.0, 4.0];
    let mut totals = vec![Agreement::default(); shifts.len()];
    for (i, held) in train_pieces.iter().enumerate() {
        let seqs: Vec<Sequence> = train_pieces
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .flat_map(|(_, p)| p.sequences.iter().map(|s| sequence(s)))
            .collect();
        let net = train(&seqs, epochs, 1, channels)?;
        let (ls, lp) = predict(&net, &held.midi)?;
        let mut line = format!("{:10}", held.name);
        for (k, &shift) in shifts.iter().enumerate() {
            let a = agreement(held, &decode(&held.midi, &ls, &lp, shift));
            let (s, sp, _) = a.shares();
            line += &format!("  shift {shift}: {s:.3}/{sp:.3}");
            totals[k].add(&a);
        }
        println!("{line}");
    }
    for (k, shift) in shifts.iter().enumerate() {
        let (s, sp, any) = totals[k].shares();
        println!("LOPO shift {shift}: string {s:.3}  string+position {sp:.3}  any {any:.3}");
    }
    Ok(())
}
