//! Temporary speed probe.
#![allow(clippy::unwrap_used, missing_docs)]
use candle_core::{DType, Device, Tensor};
use gru_baseline::{Config, GruBaseline, Loss};
use std::time::Instant;

fn main() {
    let cfg = Config::default();
    let vars = GruBaseline::init_vars(&cfg, 1).unwrap();
    let net = GruBaseline::new(
        &cfg,
        candle_nn::VarBuilder::from_varmap(&vars, DType::F32, &Device::Cpu),
    )
    .unwrap();
    let named: Vec<_> = vars
        .data()
        .lock()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    let mut adam = gru_baseline::train::Adam::new(named, 1e-3).unwrap();
    let (b, t) = (16usize, 150usize);
    let x = Tensor::randn(0f32, 1.0, (b, t, 128), &Device::Cpu).unwrap();
    let y = Tensor::randn(0f32, 0.1, (b, t, 20), &Device::Cpu).unwrap();
    let loss = Loss::default();
    let only_infer = std::env::var("ONLY_INFER").is_ok();
    for i in 0..if only_infer { 0 } else { 4 } {
        let t0 = Instant::now();
        let (p, _) = net.forward_state(&x, None, true).unwrap();
        let t1 = t0.elapsed();
        let l = loss.compute(&p, &y, None).unwrap();
        let g = l.backward().unwrap();
        let t2 = t0.elapsed();
        adam.step(&g, Some(1.0)).unwrap();
        println!(
            "step {i}: fwd {:?} fwd+bwd {:?} total {:?} loss {}",
            t1,
            t2,
            t0.elapsed(),
            l.to_scalar::<f32>().unwrap()
        );
    }
    let mel = ndarray::Array2::<f32>::from_elem((5400, 128), -30.0);
    for (rows, len) in if only_infer {
        vec![]
    } else {
        vec![(9usize, 750usize), (18, 450), (36, 225), (54, 150)]
    } {
        let m = ndarray::Array2::<f32>::from_elem((len, 128), -30.0);
        let views: Vec<_> = (0..rows).map(|_| m.view()).collect();
        let t0 = Instant::now();
        let out = net.predict_normalized_batch(&views).unwrap();
        println!("batched {rows} x {len}: {:?} ({})", t0.elapsed(), out.len());
    }
    for _ in 0..2 {
        let t0 = Instant::now();
        let out = net.predict_normalized(mel.view()).unwrap();
        println!("infer 180 s: {:?} ({:?})", t0.elapsed(), out.dim());
    }
}
