#![allow(clippy::unwrap_used, clippy::expect_used)]
//! Bad inputs give typed errors; the sequential inference carries the state exactly across
//! segments; one chunk is the sequential run; the weighted loss does the arithmetic of SPEC §8.

use candle_core::{DType, Device, Tensor};
use gru_baseline::{
    Chunking, Config, GruBaseline, GruError, Loss, TargetSpace, VideoNorm, CHUNK_FRAMES,
};
use ndarray::{Array2, Array3};

fn tiny() -> GruBaseline {
    tiny_with_lookahead(Config::default().lookahead_frames)
}

fn tiny_with_lookahead(lookahead_frames: usize) -> GruBaseline {
    let cfg = Config {
        hidden: vec![6, 10, 6],
        lookahead_frames,
        ..Config::default()
    };
    let vars = GruBaseline::init_vars(&cfg, 9).unwrap();
    GruBaseline::new(
        &cfg,
        candle_nn::VarBuilder::from_varmap(&vars, DType::F32, &Device::Cpu),
    )
    .unwrap()
}

fn mel(frames: usize) -> Array2<f32> {
    Array2::from_shape_fn((frames, 128), |(t, b)| {
        ((t * 13 + b * 7) % 23) as f32 * 0.2 - 2.0
    })
}

#[test]
fn bad_mel_inputs_are_typed_errors() {
    let net = tiny();
    assert!(matches!(
        net.predict_normalized(Array2::zeros((0, 128)).view()),
        Err(GruError::Empty(_))
    ));
    assert!(matches!(
        net.predict_normalized(Array2::zeros((10, 64)).view()),
        Err(GruError::Shape { .. })
    ));
    let mut m = mel(20);
    m[[3, 5]] = f32::NAN;
    match net.predict_normalized(m.view()) {
        Err(GruError::NonFinite { index, .. }) => assert_eq!(index, 3 * 128 + 5),
        other => panic!("{other:?}"),
    }
    m[[3, 5]] = f32::INFINITY;
    assert!(matches!(
        net.predict_mel(m.view()),
        Err(GruError::NonFinite { .. })
    ));
    let batch = [mel(5), Array2::zeros((0, 128))];
    let views: Vec<_> = batch.iter().map(|m| m.view()).collect();
    assert!(matches!(
        net.predict_normalized_batch(&views),
        Err(GruError::Empty(_))
    ));
    // The network itself checks its tensor shapes.
    let x = Tensor::zeros((1, 5, 100), DType::F32, &Device::Cpu).unwrap();
    assert!(matches!(
        net.forward_t(&x, false),
        Err(GruError::Shape { .. })
    ));
    let x = Tensor::zeros((1, 0, 128), DType::F32, &Device::Cpu).unwrap();
    assert!(matches!(net.forward_t(&x, false), Err(GruError::Empty(_))));
    let x = Tensor::zeros((5, 128), DType::F32, &Device::Cpu).unwrap();
    assert!(net.forward_t(&x, false).is_err());
}

#[test]
fn sequential_inference_equals_one_pass_and_batches_equal_singles() {
    // With an output delay of 3 frames: input padded by 3 frames, output frame t is the
    // network's output at input frame t + 3.
    let delay = 3;
    let net = tiny_with_lookahead(delay);
    let frames = 2 * CHUNK_FRAMES + 17;
    let m = mel(frames);
    let chunked = net.predict_normalized_exact(m.view()).unwrap();
    assert_eq!(chunked.dim(), (frames, 20));
    let x = net.mel_stats().normalize(m.view());
    let mut padded: Vec<f32> = x.iter().copied().collect();
    padded.resize((frames + delay) * 128, 0.0);
    let xs = Tensor::from_vec(padded, (1, frames + delay, 128), &Device::Cpu).unwrap();
    let whole = net.forward_t(&xs, false).unwrap().squeeze(0).unwrap();
    let whole = net.target_space().destandardize(
        ndarray::Array2::from_shape_vec(
            (frames + delay, 20),
            whole.flatten_all().unwrap().to_vec1::<f32>().unwrap(),
        )
        .unwrap(),
    );
    let mut max = 0f32;
    for t in 0..frames {
        for k in 0..20 {
            max = max.max((whole[[t + delay, k]] - chunked[[t, k]]).abs());
        }
    }
    assert!(max < 1e-5, "sequential vs whole: {max}");
    let short = mel(40);
    let views = [m.view(), short.view()];
    let batch = net.predict_normalized_batch(&views).unwrap();
    assert_eq!(batch[0].dim(), (frames, 20));
    assert_eq!(batch[1].dim(), (40, 20));
    let single = net.predict_normalized_exact(short.view()).unwrap();
    let d = (&batch[1] - &single)
        .mapv(f32::abs)
        .iter()
        .cloned()
        .fold(0.0, f32::max);
    assert!(d < 1e-5, "batch vs single: {d}");
    // A recording too short to cut is one chunk: the sequential run.
    let one_chunk = net.predict_normalized(short.view()).unwrap();
    assert_eq!(one_chunk, single);
    // With a warm-up as long as the recording every chunk starts at frame 0: exact again.
    let whole_warmup = Chunking {
        warmup_frames: frames,
        max_chunk_frames: 500,
        ..Chunking::default()
    };
    let c = net
        .predict_normalized_with(m.view(), &whole_warmup)
        .unwrap();
    let d = (&c - &chunked)
        .mapv(f32::abs)
        .iter()
        .cloned()
        .fold(0.0, f32::max);
    assert!(d < 1e-5, "full warm-up vs sequential: {d}");
    // Dropout only in training mode, and seeded.
    let x = Tensor::ones((2, 7, 128), DType::F32, &Device::Cpu).unwrap();
    let eval1 = net.forward_t(&x, false).unwrap().to_vec3::<f32>().unwrap();
    let eval2 = net.forward_t(&x, false).unwrap().to_vec3::<f32>().unwrap();
    assert_eq!(eval1, eval2);
    net.set_dropout_seed(3);
    let train1 = net.forward_t(&x, true).unwrap().to_vec3::<f32>().unwrap();
    net.set_dropout_seed(3);
    let train2 = net.forward_t(&x, true).unwrap().to_vec3::<f32>().unwrap();
    assert_eq!(train1, train2);
    assert_ne!(train1, eval1);
}

#[test]
fn weighted_loss_arithmetic_by_hand() {
    // Two frames; every coordinate off by 1 in frame 0 and by 2 in frame 1, except the right
    // wrist x (coordinate 8) which is off by 3 in frame 0.
    let target = vec![0f32; 40];
    let mut pred = vec![0f32; 40];
    for k in 0..20 {
        pred[k] = 1.0;
        pred[20 + k] = 2.0;
    }
    pred[8] = 3.0;
    let p = Tensor::from_vec(pred.clone(), (1, 2, 20), &Device::Cpu).unwrap();
    let t = Tensor::from_vec(target.clone(), (1, 2, 20), &Device::Cpu).unwrap();
    // MSE: (19·1 + 9 + 20·4) / 40 = 108 / 40.
    let mse = Loss::mse()
        .compute(&p, &t, None)
        .unwrap()
        .to_scalar::<f32>()
        .unwrap();
    assert!((mse - 108.0 / 40.0).abs() < 1e-6, "{mse}");
    // Weighted (3× on coordinates 4..10: right shoulder, elbow, wrist x and y):
    // frame 0: 14·1 + 5·3·1 + 3·9 = 56; frame 1: 14·4 + 6·3·4 = 128; N = 40.
    let w = Loss::right_arm_weighted(3.0);
    let lw = w.compute(&p, &t, None).unwrap().to_scalar::<f32>().unwrap();
    assert!((lw - 184.0 / 40.0).abs() < 1e-6, "{lw}");
    // The array version agrees.
    let pa = Array2::from_shape_vec((2, 20), pred).unwrap();
    let ta = Array2::from_shape_vec((2, 20), target).unwrap();
    assert!((w.compute_array(pa.view(), ta.view()).unwrap() - 4.6).abs() < 1e-9);
    // A mask keeping only frame 1: 128 / 20.
    let mask = Tensor::from_vec(vec![0f32, 1.0], (1, 2), &Device::Cpu).unwrap();
    let lm = w
        .compute(&p, &t, Some(&mask))
        .unwrap()
        .to_scalar::<f32>()
        .unwrap();
    assert!((lm - 6.4).abs() < 1e-6, "{lm}");
    // Bad shapes and weights.
    let short = Tensor::zeros((1, 2, 10), DType::F32, &Device::Cpu).unwrap();
    assert!(matches!(
        w.compute(&short, &short, None),
        Err(GruError::Shape { .. })
    ));
    let zero_mask = Tensor::zeros((1, 2), DType::F32, &Device::Cpu).unwrap();
    assert!(matches!(
        w.compute(&p, &t, Some(&zero_mask)),
        Err(GruError::Empty(_))
    ));
    assert!(Loss {
        weights: vec![-1.0; 20]
    }
    .compute(&p, &t, None)
    .is_err());
    assert!(Loss {
        weights: vec![0.0; 20]
    }
    .validate()
    .is_err());
}

#[test]
fn normalisation_rejects_degenerate_motions_and_shapes() {
    let empty = skeleton::Motion::new(30.0, Array3::zeros((0, 10, 2))).unwrap();
    assert!(matches!(VideoNorm::of(&empty), Err(GruError::Empty(_))));
    let collapsed = skeleton::Motion::new(30.0, Array3::zeros((5, 10, 2))).unwrap();
    assert!(matches!(
        VideoNorm::of(&collapsed),
        Err(GruError::Config(_))
    ));
    let space = TargetSpace::default();
    assert!(matches!(
        space.to_motion(Array2::zeros((3, 7)).view(), 30.0),
        Err(GruError::Shape { .. })
    ));
    let m = space
        .to_motion(Array2::zeros((3, 20)).view(), 30.0)
        .unwrap();
    assert_eq!(m.frames()[[2, 4, 0]], 640.0);
    let bad = Config {
        dropout: 1.0,
        ..Config::default()
    };
    assert!(matches!(bad.validate(), Err(GruError::Config(_))));
    let bad = Config {
        hidden: vec![],
        ..Config::default()
    };
    assert!(bad.validate().is_err());
}
