//! Decoding real files of every supported format, and every kind of bad input.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use dsp_mel::{load_audio, load_audio_at, AnalysisRate, DspError};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/audio")
        .join(name)
}

/// Zero crossings per second / 2 ≈ frequency of a pure tone.
fn tone_hz(samples: &[f32], rate: u32) -> f64 {
    let crossings = samples
        .windows(2)
        .filter(|w| (w[0] < 0.0) != (w[1] < 0.0))
        .count();
    crossings as f64 / 2.0 / (samples.len() as f64 / f64::from(rate))
}

#[test]
fn every_format_decodes_to_mono_at_its_rate() {
    for (name, rate) in [
        ("a440_22050_1ch.flac", 22_050),
        ("a440_44100_2ch.ogg", 44_100),
        ("a440_44100_1ch.mp3", 44_100),
        ("a440_48000_2ch.wav", 48_000),
        ("a440_16000_1ch.f32.wav", 16_000),
    ] {
        let audio = load_audio(fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(audio.sample_rate_hz(), rate, "{name}");
        assert!(
            (audio.duration_s() - 0.5).abs() < 0.06,
            "{name}: {} s",
            audio.duration_s()
        );
        let hz = tone_hz(audio.samples(), rate);
        assert!((hz - 440.0).abs() < 8.0, "{name}: {hz} Hz");
        assert!(
            (audio.peak() - 0.5).abs() < 0.06,
            "{name}: peak {}",
            audio.peak()
        );
    }
}

#[test]
fn resampling_on_load_keeps_pitch_and_duration() {
    let audio = load_audio_at(fixture("a440_48000_2ch.wav"), AnalysisRate::Hz(22_050)).unwrap();
    assert_eq!(audio.sample_rate_hz(), 22_050);
    assert_eq!(audio.samples().len(), 11_025);
    assert!((tone_hz(audio.samples(), 22_050) - 440.0).abs() < 5.0);
}

fn write_wav(path: &Path, samples: &[f32], rate: u32) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for s in samples {
        w.write_sample(*s).unwrap();
    }
    w.finalize().unwrap();
}

#[test]
fn missing_file() {
    let err = load_audio("/definitely/not/here.wav").unwrap_err();
    assert!(matches!(err, DspError::NotFound { .. }), "{err}");
    assert!(err.to_string().contains("not/here.wav"));
}

#[test]
fn directory_instead_of_file() {
    let dir = tempfile::tempdir().unwrap();
    assert!(matches!(
        load_audio(dir.path()).unwrap_err(),
        DspError::IsDirectory { .. }
    ));
}

#[test]
fn empty_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("empty.wav");
    std::fs::write(&p, b"").unwrap();
    assert!(matches!(
        load_audio(&p).unwrap_err(),
        DspError::EmptyFile { .. }
    ));
}

#[test]
fn not_audio_at_all() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["notes.wav", "notes.mp3", "notes.flac", "notes"] {
        let p = dir.path().join(name);
        std::fs::write(&p, "this is a text file, not a recording\n".repeat(50)).unwrap();
        let err = load_audio(&p).unwrap_err();
        assert!(
            matches!(err, DspError::Unsupported { .. } | DspError::Corrupt { .. }),
            "{name}: {err}"
        );
    }
}

#[test]
fn header_only_wav_has_no_samples() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("header.wav");
    write_wav(&p, &[], 22_050);
    let err = load_audio(&p).unwrap_err();
    assert!(
        matches!(err, DspError::NoSamples { .. } | DspError::Corrupt { .. }),
        "{err}"
    );
}

#[test]
fn truncated_wav_keeps_what_is_there() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cut.wav");
    write_wav(&p, &vec![0.25; 10_000], 22_050);
    let bytes = std::fs::read(&p).unwrap();
    std::fs::write(&p, &bytes[..44 + 4 * 6_000 + 2]).unwrap();
    let audio = load_audio(&p).unwrap();
    assert!(audio.samples().len() >= 5_000 && audio.samples().len() <= 6_000);
    assert!(audio.samples().iter().all(|&s| s == 0.25));
}

#[test]
fn truncated_mp3_keeps_what_is_there_or_says_corrupt() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(fixture("a440_44100_1ch.mp3")).unwrap();
    let p = dir.path().join("cut.mp3");
    std::fs::write(&p, &bytes[..bytes.len() / 2]).unwrap();
    match load_audio(&p) {
        Ok(a) => assert!(a.duration_s() < 0.45 && a.duration_s() > 0.05),
        Err(e) => assert!(matches!(e, DspError::Corrupt { .. }), "{e}"),
    }
}

#[test]
fn corrupt_mp3_never_panics() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = std::fs::read(fixture("a440_44100_1ch.mp3")).unwrap();
    // Scramble everything after the first frame header.
    let mut state = 12345u32;
    for b in bytes.iter_mut().skip(600) {
        state = state.wrapping_mul(1_103_515_245).wrapping_add(12345);
        *b = (state >> 16) as u8;
    }
    let p = dir.path().join("garbled.mp3");
    std::fs::write(&p, &bytes).unwrap();
    if let Ok(a) = load_audio(&p) {
        assert!(a.samples().iter().all(|s| s.is_finite()));
    }
}

#[test]
fn a_stream_that_panics_the_vorbis_decoder_is_a_corrupt_file() {
    // Found by `input-fuzz ogg` (seed 20261126, mutant 622 of the a440 Ogg fixture): the
    // codebook setup asserts inside the codec library.
    let err = load_audio(fixture("vorbis_codebook_panic.ogg")).unwrap_err();
    assert!(matches!(err, DspError::Corrupt { .. }), "{err}");
    assert!(
        err.to_string().contains("vorbis_codebook_panic.ogg"),
        "{err}"
    );
}

#[test]
fn a_header_sample_rate_outside_audio_rates_is_a_corrupt_file() {
    // Found by `input-fuzz all --iterations 2000 --seed 7`: a WAV whose header says 1 Hz
    // lasted 33 075 s and took 8 minutes to resample. 1 Hz and 3 999 Hz are refused at open,
    // 4 kHz is read.
    let dir = tempfile::tempdir().unwrap();
    for (rate, ok) in [(1u32, false), (3_999, false), (4_000, true)] {
        let p = dir.path().join(format!("r{rate}.wav"));
        write_wav(&p, &vec![0.1f32; 2_000], rate);
        match load_audio(&p) {
            Ok(a) => assert!(ok && a.sample_rate_hz() == rate),
            Err(e) => {
                assert!(!ok, "{rate} Hz: {e}");
                assert!(e.to_string().contains(&format!("{rate} Hz")), "{e}");
            }
        }
    }
}

#[test]
fn nan_samples_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("nan.wav");
    let mut samples = vec![0.1f32; 1000];
    samples[500] = f32::NAN;
    write_wav(&p, &samples, 22_050);
    assert!(matches!(
        load_audio(&p).unwrap_err(),
        DspError::NonFinite { index: 500, .. }
    ));
}

#[test]
fn silence_loads_as_zeros() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("silent.wav");
    write_wav(&p, &[0.0; 2205], 22_050);
    let audio = load_audio(&p).unwrap();
    assert_eq!(audio.samples().len(), 2205);
    assert_eq!(audio.peak(), 0.0);
}

#[test]
fn reading_in_pieces_gives_the_same_samples_for_every_format() {
    for name in [
        "a440_22050_1ch.flac",
        "a440_44100_2ch.ogg",
        "a440_44100_1ch.mp3",
        "a440_48000_2ch.wav",
    ] {
        let whole = load_audio(fixture(name)).unwrap();
        let mut reader = dsp_mel::AudioReader::open(fixture(name)).unwrap();
        assert_eq!(reader.sample_rate_hz(), whole.sample_rate_hz(), "{name}");
        let mut pieces = Vec::new();
        let mut piece = Vec::new();
        loop {
            piece.clear();
            let n = reader.read_mono(1234, &mut piece).unwrap();
            if n == 0 {
                break;
            }
            assert!(n <= 1234);
            pieces.extend_from_slice(&piece);
        }
        assert_eq!(pieces, whole.samples(), "{name}");
        assert_eq!(reader.samples_read(), whole.samples().len(), "{name}");
    }
}

#[test]
fn reading_in_pieces_reports_nan_at_its_file_index() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("nan.wav");
    let mut samples = vec![0.1f32; 5000];
    samples[3210] = f32::NAN;
    write_wav(&p, &samples, 22_050);
    let mut reader = dsp_mel::AudioReader::open(&p).unwrap();
    let mut out = Vec::new();
    let err = loop {
        match reader.read_mono(1000, &mut out) {
            Ok(0) => panic!("the NaN was not reported"),
            Ok(_) => out.clear(),
            Err(e) => break e,
        }
    };
    assert!(
        matches!(err, DspError::NonFinite { index: 3210, .. }),
        "{err}"
    );
}
