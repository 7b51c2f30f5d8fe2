"""Python and the command-line tool give the same results on the same file."""

import json
import subprocess

import numpy as np

import violin_skeleton as vs


def run(cli, *args):
    subprocess.run([str(cli), "--quiet", *map(str, args)], check=True)


def test_analysis_json_equals_the_cli(cli, demo_wav, tmp_path):
    run(cli, "analyze", demo_wav, "-o", tmp_path / "cli.json")
    vs.analyze(demo_wav).save(tmp_path / "py.json")
    cli_json = (tmp_path / "cli.json").read_bytes()
    assert cli_json == (tmp_path / "py.json").read_bytes()
    assert json.loads(cli_json) == vs.analyze(demo_wav).to_dict()


def test_motion_equals_the_cli(cli, demo_wav, tmp_path):
    run(cli, "generate", demo_wav, "-o", tmp_path / "cli.npy")
    run(cli, "generate", demo_wav, "-o", tmp_path / "cli.json")
    m = vs.generate(demo_wav)
    np.testing.assert_array_equal(np.load(tmp_path / "cli.npy"), m.joints.reshape(len(m), -1))
    m.save(tmp_path / "py.json")
    assert (tmp_path / "cli.json").read_bytes() == (tmp_path / "py.json").read_bytes()
    cli_motion = json.loads((tmp_path / "cli.json").read_text())
    np.testing.assert_allclose(np.array(cli_motion["frames_3d"]), m.joints_3d, rtol=0, atol=1e-4)


def test_gru_motion_equals_the_cli(cli, demo_wav, tmp_path):
    run(cli, "generate", demo_wav, "--method", "gru", "-o", tmp_path / "cli.npy")
    m = vs.generate(demo_wav, method="gru")
    np.testing.assert_array_equal(np.load(tmp_path / "cli.npy"), m.joints.reshape(len(m), -1))


def test_features_equal_the_cli(cli, demo_wav, tmp_path):
    for kind in ("mel30", "mel2"):
        run(cli, "features", demo_wav, "--kind", kind, "-o", tmp_path / f"{kind}.npy")
        np.testing.assert_array_equal(np.load(tmp_path / f"{kind}.npy"),
                                      vs.features(demo_wav, kind=kind))


def test_openpose_and_glb_equal_the_cli(cli, demo_wav, tmp_path):
    run(cli, "generate", demo_wav, "-o", tmp_path / "cli_pose")
    run(cli, "generate", demo_wav, "-o", tmp_path / "cli.glb")
    m = vs.generate(str(demo_wav))
    m.save(str(tmp_path / "py_pose"))
    m.save(str(tmp_path / "py.glb"))
    assert (tmp_path / "py.glb").read_bytes() == (tmp_path / "cli.glb").read_bytes()
    cli_files = sorted(p.name for p in (tmp_path / "cli_pose").iterdir())
    py_files = sorted(p.name for p in (tmp_path / "py_pose").iterdir())
    assert len(cli_files) == len(m) == len(py_files)
    for a, b in zip(cli_files[:: max(1, len(m) // 10)], py_files[:: max(1, len(m) // 10)]):
        assert (tmp_path / "cli_pose" / a).read_text().replace("cli_pose", "") == (
            tmp_path / "py_pose" / b
        ).read_text().replace("py_pose", "")
