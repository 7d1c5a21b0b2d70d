import csv
import json
import os

import pytest

from harness.config_hash import planned_config_hash  # the development harness at the repository root
from sklearn_hardness._cli import main
from sklearn_hardness._cli._header import read_header
from sklearn_hardness.io import write_video

from ._exp_data import tiny_presses, write_object_manifest


@pytest.fixture(scope="module")
def manifest(tmp_path_factory):
    data = tiny_presses()
    folder = tmp_path_factory.mktemp("recordings")
    with open(folder / "manifest.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["path", "label", "hardness", "hardness_unit"])
        for i in range(len(data.videos)):
            name = f"press_{i:03d}.npy"
            write_video(folder / name, data.videos[i])
            c = int(data.target[i])
            w.writerow([name, data.target_names[c], data.hardness[c], "mm/N"])
    return folder / "manifest.csv"


@pytest.mark.slow
def test_reproduce_on_a_manifest(manifest, tmp_path, capsys):
    out = tmp_path / "out"
    args = ["reproduce", "--dataset", str(manifest), "--model", "ofnn", "--out", str(out), "--n-runs", "1",
            "--strategies", "variance", "random", "--epochs", "4", "2", "--quiet", "--set", "n_iterations=2",
            "n_per_query=2", "n_initial=2", "n_test=2", "max_reservoir=8", "n_samples=4",
            "frame_size=(16,20)"]
    assert main(args) == 0
    text = capsys.readouterr().out
    for name in ("no resampling", "variance", "random", "humans (paper)", "48.00% +- 22.27%", "MAE (mm/N)"):
        assert name in text
    assert "entropy" not in text.split("humans")[0].split("\n", 2)[2]
    files = set(os.listdir(out))
    assert {"results.jsonl", "table.txt", "paired.txt", "config.json", "accuracy.png", "mae.png",
            "entropy.png", "variance.png"} <= files
    paired = (out / "paired.txt").read_text()
    assert "- random [95% CI]" in paired and "presses_at_stop" in paired and "variance" in paired
    # both tables start with their header; its config hash is the one the harness plans from the command
    record = read_header((out / "table.txt").read_text())
    assert read_header(paired) == record and record["command"].startswith("sklearn-hardness reproduce --dataset")
    assert record["config_hash"] == planned_config_hash(["sklearn-hardness", *args])
    lines = (out / "results.jsonl").read_text().splitlines()
    assert len(lines) == 2 * 5  # strategies x test objects x 1 seed
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["initial_epochs"] == 4 and cfg["n_iterations"] == 2 and cfg["model"] == "ofnn"
    # the same command again resumes: nothing is recomputed
    before = (out / "results.jsonl").read_bytes()
    assert main(args) == 0
    assert (out / "results.jsonl").read_bytes() == before


@pytest.mark.slow
def test_reproduce_on_a_manifest_of_many_objects_is_object_disjoint(tmp_path, capsys):
    data = tiny_presses()
    folder = tmp_path / "recordings"
    folder.mkdir()
    write_object_manifest(folder, data, presses_per_object=4)  # 2 objects a class
    out = tmp_path / "out"
    args = ["reproduce", "--dataset", str(folder / "manifest.csv"), "--model", "ofnn", "--out", str(out),
            "--n-runs", "1", "--strategies", "variance", "random", "--epochs", "4", "2", "--quiet", "--set",
            "n_iterations=2", "n_per_query=2", "n_initial=2", "n_test=2", "max_reservoir=8", "n_samples=4",
            "frame_size=(16,20)"]
    assert main(args) == 0
    header = capsys.readouterr().out.splitlines()[0]
    assert header.startswith(f"{folder / 'manifest.csv'} (silicone5 settings, object-disjoint protocol)")
    paired = (out / "paired.txt").read_text()
    # what a robot user wants comes first: presses to reach random, then presses and accuracy at the stop
    assert paired.index("presses to reach it") < paired.index("presses_at_stop")
    metrics = [line.split()[1] for line in paired.splitlines() if line.startswith("variance ")
               and line.split()[1] in ("presses_at_stop", "accuracy_at_stop", "accuracy", "auc", "mae")]
    assert metrics[:3] == ["presses_at_stop", "accuracy_at_stop", "accuracy"]
    records = [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]
    assert len(records) == 2 * 10  # strategies x test objects (2 per class) x 1 seed
    assert {r["key"]["test_object"] for r in records} == {f"object{c}-{k}" for c in range(5) for k in (0, 1)}


def test_reproduce_help_and_bad_input(capsys, tmp_path):
    with pytest.raises(SystemExit):
        main(["reproduce", "--help"])
    assert "--quick" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["reproduce", "--preset", "yuan"])
    with pytest.raises(SystemExit, match="2"):
        main(["reproduce", "--set", "n_iteration=2", "--out", str(tmp_path)])
    assert "unknown configuration key" in capsys.readouterr().err
    with pytest.raises(SystemExit, match="2"):
        main(["reproduce", "--set", "n_mc_samples=4", "--out", str(tmp_path)])
    assert "'n_mc_samples' is now 'n_samples'" in capsys.readouterr().err
    with pytest.raises(SystemExit, match="2"):
        main(["reproduce", "--strategies", "uncertainty", "--out", str(tmp_path), "--dataset", "x.csv"])
    assert "strategy" in capsys.readouterr().err
