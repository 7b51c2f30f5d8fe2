"""Bad input raises a clear exception (never a crash), each kind naming what is wrong."""

import numpy as np
import pytest

import violin_skeleton as vs

SR = 22050


def tone(seconds=2.0, sr=SR):
    t = np.arange(int(seconds * sr)) / sr
    return (0.3 * np.sin(2 * np.pi * 440 * t)).astype(np.float32)


def test_missing_file(tmp_path):
    missing = tmp_path / "nope.wav"
    for call in (vs.analyze, vs.generate, vs.features):
        with pytest.raises(FileNotFoundError, match="nope.wav") as e:
            call(missing)
        assert isinstance(e.value, vs.ViolinSkeletonError)
        assert isinstance(e.value, vs.InputNotFoundError)


def test_missing_midi_file(tmp_path):
    with pytest.raises(vs.InputNotFoundError, match="piece.mid"):
        vs.analyze(tmp_path / "piece.mid")


def test_directory(tmp_path):
    with pytest.raises(IsADirectoryError, match="is a directory") as e:
        vs.analyze(tmp_path)
    assert isinstance(e.value, vs.ViolinSkeletonError)
    assert str(tmp_path) in str(e.value)


def test_not_audio_names_the_file(tmp_path):
    bad = tmp_path / "notes.wav"
    bad.write_text("this is not audio")
    with pytest.raises(vs.ViolinSkeletonError, match="notes.wav"):
        vs.analyze(bad)


def test_empty_array():
    with pytest.raises(ValueError, match="empty"):
        vs.analyze(np.zeros(0, dtype=np.float32), sr=SR)
    with pytest.raises(ValueError, match="empty"):
        vs.analyze(np.zeros((2, 0), dtype=np.float32), sr=SR)


def test_three_dimensional_array():
    with pytest.raises(vs.InvalidInputError, match="3 dimensions"):
        vs.analyze(np.zeros((2, 2, 1000), dtype=np.float32), sr=SR)


def test_scalar_array():
    with pytest.raises(vs.InvalidInputError, match="0 dimensions"):
        vs.analyze(np.array(0.5, dtype=np.float32), sr=SR)


def test_too_many_channels():
    with pytest.raises(vs.InvalidInputError, match="channels"):
        vs.analyze(np.zeros((100, 200), dtype=np.float32), sr=SR)


def test_integer_array():
    pcm = (tone() * 32767).astype(np.int16)
    with pytest.raises(TypeError, match="int16.*float32") as e:
        vs.analyze(pcm, sr=SR)
    assert isinstance(e.value, vs.InputTypeError)


def test_other_non_float_arrays():
    for arr in (np.zeros(100, dtype=bool), np.zeros(100, dtype=np.complex64),
                np.array(["a", "b"]), np.zeros(100, dtype=object)):
        with pytest.raises(vs.InputTypeError, match="dtype"):
            vs.analyze(arr, sr=SR)


def test_nan_and_inf():
    x = tone()
    x[1234] = np.nan
    with pytest.raises(ValueError, match="NaN.*1234"):
        vs.analyze(x, sr=SR)
    y = np.stack([tone(), tone()])
    y[1, 7] = np.inf
    with pytest.raises(vs.InvalidInputError, match=r"\[1, 7\]"):
        vs.generate(y, sr=SR)


@pytest.mark.parametrize("sr", [0, -44100, 44100.5, float("nan"), 10**9])
def test_bad_sample_rate(sr):
    with pytest.raises(vs.InvalidInputError, match="sr="):
        vs.analyze(tone(), sr=sr)


def test_sample_rate_of_wrong_type():
    with pytest.raises(vs.InputTypeError, match="sr must be"):
        vs.analyze(tone(), sr="44100")


def test_array_without_sample_rate():
    for call in (vs.analyze, vs.generate, vs.features):
        with pytest.raises(vs.InvalidInputError, match="needs its sample rate"):
            call(tone())


def test_sample_rate_with_a_path(tmp_path):
    with pytest.raises(vs.InvalidInputError, match="sr is only for arrays"):
        vs.analyze(tmp_path / "x.wav", sr=SR)


def test_wrong_argument_types():
    for value in (3, 2.5, None, [0.1, 0.2], object()):
        with pytest.raises(TypeError):
            vs.analyze(value, sr=SR)


def test_bad_options(demo_samples, tmp_path):
    with pytest.raises(vs.InvalidInputError, match="method"):
        vs.Pipeline(method="magic")
    with pytest.raises(vs.InvalidInputError, match="method"):
        vs.generate(tone(), sr=SR, method="magic")
    with pytest.raises(vs.InvalidInputError, match="kind"):
        vs.features(tone(), kind="mfcc", sr=SR)
    samples, rate = demo_samples
    m = vs.generate(samples[: rate * 4], sr=rate)
    with pytest.raises(vs.InvalidInputError, match="format"):
        m.save(tmp_path / "m.json", format="gif")
    with pytest.raises(vs.InvalidInputError, match="m.txt"):
        m.save(tmp_path / "m.txt")
    with pytest.raises(vs.ViolinSkeletonError, match="does not exist"):
        m.save(tmp_path / "no" / "such" / "m.json")
    a = vs.analyze(samples[: rate * 4], sr=rate)
    with pytest.raises(vs.ViolinSkeletonError, match="is a directory"):
        a.save(tmp_path)


def test_silence_and_too_short_are_errors_not_crashes():
    with pytest.raises(vs.ViolinSkeletonError):
        vs.generate(np.zeros(SR // 4, dtype=np.float32), sr=SR)
    # Analysing silence is allowed: it finds nothing.
    a = vs.analyze(np.zeros(SR * 2, dtype=np.float32), sr=SR)
    assert a.notes == []
