"""The distributed recipe (examples/dask_batch.py) on a local Dask cluster of 2 workers:
outputs equal the package's own, a broken and a missing file are listed as failures, and
--skip-existing resumes."""

import importlib.util
import json
import pathlib
import shutil

import numpy as np
import pytest

import violin_skeleton

RECIPE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "dask_batch.py"


def _recipe():
    spec = importlib.util.spec_from_file_location("dask_batch", RECIPE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def collection(demo_wav, tmp_path_factory):
    root = tmp_path_factory.mktemp("takes")
    (root / "day2").mkdir()
    shutil.copy(demo_wav, root / "a.wav")
    shutil.copy(demo_wav, root / "day2" / "b.wav")
    (root / "broken.wav").write_bytes(b"not a wave file")
    files = [root / "a.wav", root / "day2" / "b.wav", root / "broken.wav", root / "missing.wav"]
    listing = root / "list.txt"
    listing.write_text("\n".join(str(f) for f in files) + "\n")
    return root, listing


def test_recipe_on_a_local_cluster_of_two_workers(collection, tmp_path):
    root, listing = collection
    recipe = _recipe()
    out = tmp_path / "motion"
    code = recipe.main(
        ["--files", str(listing), "--root", str(root), "--out", str(out), "--local", "2"]
    )
    assert code == 1  # two files failed
    failures = json.loads((out / "failures.json").read_text())
    assert sorted(pathlib.Path(f["file"]).name for f in failures) == ["broken.wav", "missing.wav"]
    assert all(f["error"] for f in failures)
    expected = violin_skeleton.generate(str(root / "a.wav"))
    for rel in ["a.json", "day2/b.json"]:
        data = json.loads((out / rel).read_text())
        assert np.array_equal(np.asarray(data["frames"], dtype=np.float32), expected.joints)

    # Resume: the written files are left alone.
    before = (out / "a.json").stat().st_mtime_ns
    code = recipe.main(
        ["--files", str(listing), "--root", str(root), "--out", str(out), "--local", "2",
         "--skip-existing", "--kind", "generate"]
    )
    assert code == 1
    assert (out / "a.json").stat().st_mtime_ns == before


def test_recipe_analyze_equals_the_package(collection, tmp_path):
    root, listing = collection
    listing2 = tmp_path / "two.txt"
    listing2.write_text(f"{root / 'a.wav'}\n{root / 'day2' / 'b.wav'}\n")
    out = tmp_path / "analyses"
    code = _recipe().main(
        ["--files", str(listing2), "--root", str(root), "--out", str(out), "--local", "2",
         "--kind", "analyze"]
    )
    assert code == 0
    assert json.loads((out / "failures.json").read_text()) == []
    assert json.loads((out / "day2" / "b.json").read_text()) == violin_skeleton.analyze(
        str(root / "day2" / "b.wav")
    ).to_dict()
