"""The API: shapes, types, dicts, files, and one pipeline reused."""

import json
import threading

import numpy as np
import pytest

import violin_skeleton as vs


def test_candle_elementwise_ops_stay_on_one_thread_unless_the_user_chose():
    import os
    import subprocess
    import sys

    code = "import os, violin_skeleton; print(os.environ['CANDLE_NUM_THREADS'])"
    env = {k: v for k, v in os.environ.items() if k != "CANDLE_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.stdout.strip() == "1", out.stderr
    env["CANDLE_NUM_THREADS"] = "2"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.stdout.strip() == "2", out.stderr


def test_import_exposes_the_api():
    for name in ["analyze", "generate", "features", "Pipeline", "Analysis", "Motion",
                 "ViolinSkeletonError"]:
        assert hasattr(vs, name), name
    assert vs.__version__


def test_analyze_a_file_gives_numpy_arrays(demo_wav):
    a = vs.analyze(demo_wav)
    assert isinstance(a, vs.Analysis)
    assert a.f0_hz.dtype == np.float32 and a.f0_hz.ndim == 1
    assert a.voiced_prob.shape == a.f0_hz.shape
    assert ((a.voiced_prob >= 0) & (a.voiced_prob <= 1)).all()
    for name in ["beats_s", "downbeats_s", "bow_changes_s"]:
        times = getattr(a, name)
        assert times.dtype == np.float64, name
        assert (np.diff(times) > 0).all(), name
        assert ((times >= 0) & (times <= a.duration_s)).all(), name
    assert len(a.beats_s) > 4 and len(a.bow_changes_s) > 4
    assert set(a.downbeats_s) <= set(a.beats_s) or len(a.downbeats_s) > 0
    assert a.arousal.dtype == np.float32 and a.arousal_rate_hz == 2
    assert abs(len(a.arousal) - a.duration_s * 2) <= 2
    assert 40 < a.tempo_bpm < 240
    assert a.source == "audio" and a.sample_rate == 22050
    notes = a.notes
    assert len(notes) > 10
    assert {"onset_s", "offset_s", "midi"} <= set(notes[0])
    assert all(n["offset_s"] > n["onset_s"] for n in notes)
    assert "notes" in repr(a)


def test_to_dict_is_the_json(demo_wav, tmp_path):
    a = vs.analyze(str(demo_wav))
    d = a.to_dict()
    assert d == json.loads(a.to_json())
    assert d["beats_s"] == a.beats_s.tolist()
    assert np.allclose(d["f0"]["hz"], a.f0_hz)
    out = tmp_path / "analysis.json"
    a.save(out)
    assert json.loads(out.read_text()) == d


def test_analyze_an_array_equals_the_file(demo_wav, demo_samples):
    samples, rate = demo_samples
    from_file = vs.analyze(demo_wav)
    from_array = vs.analyze(samples, sr=rate)
    assert from_array.to_dict() == from_file.to_dict()
    # float64 and (channels, samples) / (samples, channels) stereo give the same.
    stereo = np.stack([samples, samples]).astype(np.float64)
    assert vs.analyze(stereo, sr=rate).to_dict() == from_file.to_dict()
    assert vs.analyze(stereo.T, sr=rate).to_dict() == from_file.to_dict()


def test_generate_gives_joints(demo_wav, tmp_path):
    m = vs.generate(demo_wav)
    assert isinstance(m, vs.Motion)
    assert m.fps == 30
    assert m.joints.dtype == np.float32
    assert m.joints.shape == (len(m), 10, 2)
    assert m.joints_3d.shape == (len(m), 10, 3)
    assert m.joint_names[:3] == ["nose", "neck", "r_shoulder"]
    assert abs(len(m) / m.fps - m.duration_s) < 1e-9
    assert np.isfinite(m.joints).all()
    assert m.joints.std(axis=0).max() > 1.0  # it moves
    for name in ["m.json", "m.csv", "m.npy", "m.bvh"]:
        m.save(tmp_path / name)
        assert (tmp_path / name).stat().st_size > 100, name
    np.testing.assert_array_equal(np.load(tmp_path / "m.npy"), m.joints.reshape(len(m), -1))
    m.save(tmp_path / "pose")  # no extension: an OpenPose folder
    assert len(list((tmp_path / "pose").glob("*_keypoints.json"))) == len(m)
    m.save(tmp_path / "other.txt", format="json")
    assert json.loads((tmp_path / "other.txt").read_text())["fps"] == 30


def test_generate_gru_has_no_3d(demo_samples):
    samples, rate = demo_samples
    m = vs.generate(samples, sr=rate, method="gru")
    assert m.joints.shape == (len(m), 10, 2)
    assert m.joints_3d is None


def test_features_shapes(demo_wav, demo_samples):
    mel = vs.features(demo_wav)
    assert mel.dtype == np.float32 and mel.ndim == 2 and mel.shape[1] == 128
    duration_s = len(demo_samples[0]) / demo_samples[1]
    assert abs(mel.shape[0] - duration_s * 30) <= 2
    assert vs.features(demo_wav, kind="mel2").shape[1] == 64
    samples, rate = demo_samples
    np.testing.assert_array_equal(vs.features(samples, sr=rate), mel)


def test_one_pipeline_is_reused_and_thread_safe(demo_samples):
    samples, rate = demo_samples
    clip = samples[: rate * 8]
    p = vs.Pipeline()
    first = p.analyze(clip, sr=rate).to_dict()
    results = [None] * 3

    def work(i):
        results[i] = p.analyze(clip, sr=rate).to_dict()

    threads = [threading.Thread(target=work, args=(i,)) for i in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(r == first for r in results)
    assert vs.default_pipeline() is vs.default_pipeline("rules")
    assert "rules" in repr(p)


def test_gil_is_released_while_analysing(demo_samples):
    samples, rate = demo_samples
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.005)

    t = threading.Thread(target=ticker)
    t.start()
    before = len(ticks)
    vs.Pipeline().analyze(samples, sr=rate)
    during = len(ticks) - before
    stop.set()
    t.join()
    assert during > 5, "the Python thread did not run while the analysis worked"


def test_beat_hints_set_the_metre_and_tempo(demo_samples):
    samples, rate = demo_samples
    clip = samples[: rate * 10]
    a = vs.Pipeline(time_signature="6/8", tempo_bpm=(52, 70)).analyze(clip, sr=rate)
    meter = a.to_dict()["meter"]
    assert (meter["beats_per_bar"], meter["subdivisions"]) == (2, 3)
    assert 52 <= a.tempo_bpm <= 70
    for bad in [
        dict(time_signature="3/5"),
        dict(tempo_bpm="fast"),
        dict(tempo_bpm=(140, 100)),
        dict(beats="classic", time_signature="3/4"),
    ]:
        with pytest.raises(ValueError):
            vs.Pipeline(**bad)
