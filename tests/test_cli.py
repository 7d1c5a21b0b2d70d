import subprocess
import sys

import pytest

from sklearn_hardness._cli import main

from .test_datasets_manifest import _write_dataset


def test_select_command(tmp_path, capsys):
    manifest, _ = _write_dataset(tmp_path)
    assert main(["select", str(manifest), "--n-between", "1", "--plot", str(tmp_path / "c.png")]) == 0
    out = capsys.readouterr().out
    assert "contact found in 6 of 6 videos" in out
    assert (tmp_path / "c.png").stat().st_size > 1000


def test_select_takes_a_folder_holding_the_manifest(tmp_path, capsys):
    # as evaluate does
    _write_dataset(tmp_path)
    assert main(["select", str(tmp_path), "--n-between", "1"]) == 0
    assert "contact found in 6 of 6 videos" in capsys.readouterr().out


def test_no_command_prints_help(capsys):
    assert main([]) == 2
    assert "select" in capsys.readouterr().out


def test_console_script_is_installed():
    out = subprocess.run(
        [sys.executable, "-m", "sklearn_hardness._cli", "--version"], capture_output=True, text=True, check=True
    )
    assert out.stdout.startswith("sklearn-hardness")


def test_unknown_command():
    with pytest.raises(SystemExit):
        main(["frobnicate"])


# --- wrong invocations: one error line, exit status 2, nothing written -------------------------

WRONG_INVOCATIONS = {
    "missing manifest": ["select", "{tmp}/nope.csv"],
    "threshold not a number": ["select", "{tmp}/nope.csv", "--threshold", "abc"],
    "negative threshold": ["select", "{tmp}/nope.csv", "--threshold", "-1"],
    "output of unknown format": ["select", "{tmp}/nope.csv", "--output", "{tmp}/out.txt"],
    "unknown --set key": ["reproduce", "--quick", "--set", "n_iteration=2", "--out", "{tmp}/rep"],
    "bad --set value": ["reproduce", "--quick", "--set", "n_runs=0", "--out", "{tmp}/rep"],
    "frame size below the selector's": ["reproduce", "--quick", "--set", "frame_size=1,1", "--out", "{tmp}/rep"],
    "--set without =": ["reproduce", "--set", "n_runs", "--out", "{tmp}/rep"],
    "unknown strategy": ["reproduce", "--quick", "--strategies", "uncertainty", "--out", "{tmp}/rep"],
    "--n-jobs 0 (reproduce)": ["reproduce", "--quick", "--n-jobs", "0", "--out", "{tmp}/rep"],
    "--n-jobs not an int": ["reproduce", "--quick", "--n-jobs", "two", "--out", "{tmp}/rep"],
    "--n-runs 0": ["reproduce", "--quick", "--n-runs", "0", "--out", "{tmp}/rep"],
    "missing --dataset": ["reproduce", "--quick", "--dataset", "{tmp}/nope.csv", "--out", "{tmp}/rep"],
    "unknown --test-objects": ["reproduce", "--quick", "--dataset", "everyday", "--test-objects", "nosuch",
                               "--out", "{tmp}/rep"],
    "paper protocol with --test-objects": ["reproduce", "--protocol", "paper", "--test-objects", "x",
                                           "--out", "{tmp}/rep"],
    "paper protocol with --model": ["reproduce", "--protocol", "paper", "--model", "ofnn", "--out", "{tmp}/rep"],
    "unknown preset (simulate)": ["simulate", "--preset", "foo", "--out", "{tmp}/sim"],
    "--n-jobs 0 (simulate)": ["simulate", "--n-jobs", "0", "--out", "{tmp}/sim"],
    "image size 0": ["simulate", "--image-size", "0", "10", "--out", "{tmp}/sim"],
    "camera not found": ["record", "--source", "97", "--label", "soft", "--out", "{tmp}/rec"],
    "capture file not found": ["record", "--source", "{tmp}/nope.avi", "--label", "soft", "--out", "{tmp}/rec"],
    "--n-frames 0": ["record", "--source", "97", "--label", "soft", "--out", "{tmp}/rec", "--n-frames", "0"],
    "missing dataset (evaluate)": ["evaluate", "{tmp}/nope.csv", "--pipelines"],
    "unknown pipeline": ["evaluate", "everyday", "--pipelines", "svm"],
    "--cv 1": ["evaluate", "everyday", "--cv", "1"],
    "--n-jobs 0 (evaluate)": ["evaluate", "everyday", "--n-jobs", "0"],
    "--roi upside down (evaluate)": ["evaluate", "everyday", "--roi", "0.9", "0.1", "0", "1"],
    "--roi of three numbers (evaluate)": ["evaluate", "everyday", "--roi", "0.1", "0.9", "0"],
    "--roi upside down (select)": ["select", "{tmp}/nope.csv", "--roi", "0.9", "0.1", "0", "1"],
    "cache of a missing --out": ["cache", "--out", "{tmp}/nope", "--clear"],
    "missing required --out": ["simulate"],
}


@pytest.mark.parametrize("argv", WRONG_INVOCATIONS.values(), ids=WRONG_INVOCATIONS.keys())
def test_wrong_invocation_is_one_error_line_and_writes_nothing(argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # default output folders (./hardness_results, ...) would land here
    before = sorted(p.name for p in tmp_path.rglob("*"))
    with pytest.raises(SystemExit) as info:
        main([a.format(tmp=tmp_path) for a in argv])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"sklearn-hardness {argv[0]}: error: ")
    assert sorted(p.name for p in tmp_path.rglob("*")) == before


def test_error_lines_name_the_problem(tmp_path, capsys):
    for argv, fragment in [
        (["reproduce", "--set", "n_iteration=2"], "unknown configuration key(s) ['n_iteration']"),
        (["reproduce", "--n-jobs", "0"], "argument --n-jobs: expected a non-zero integer"),
        (["select", "x.csv", "--threshold", "abc"], "expected 'auto' or a positive number, got 'abc'"),
        (["record", "--source", "97", "--label", "a", "--out", str(tmp_path / "r")], "camera 97"),
        (["evaluate", "everyday", "--roi", "0.9", "0.1", "0", "1"], "top < bottom and left < right"),
        (["select", "x.csv", "--roi", "0", "1", "0.7", "0.2"], "top < bottom and left < right"),
    ]:
        with pytest.raises(SystemExit):
            main(argv)
        assert fragment in capsys.readouterr().err


def test_reproduce_takes_a_preset_as_dataset_and_test_objects(tmp_path, monkeypatch):
    import sklearn_hardness.experiments as experiments

    seen = {}

    class Stop(Exception):
        pass

    def fake(dataset, **kw):
        seen.update(kw, dataset=dataset)
        raise Stop

    monkeypatch.setattr(experiments, "run_active_sampling", fake)
    with pytest.raises(Stop):
        main(["reproduce", "--quick", "--dataset", "everyday", "--test-objects", "everyday-00-marble",
              "--out", str(tmp_path / "rep")])
    assert seen["dataset"] == "everyday" and seen["test_objects"] == ["everyday-00-marble"]


def test_n_jobs_accepts_joblib_negatives():
    from sklearn_hardness._cli import build_parser

    args = build_parser().parse_args(["reproduce", "--n-jobs", "-1"])
    assert args.n_jobs == -1


def test_missing_camera_output_is_one_line_in_a_real_process(tmp_path):
    # OpenCV's own warnings go to the C stderr, which capsys cannot see
    out = subprocess.run([sys.executable, "-m", "sklearn_hardness._cli", "record", "--source", "97", "--label",
                          "a", "--out", str(tmp_path / "rec")], capture_output=True, text=True)
    assert out.returncode == 2
    assert out.stderr.splitlines() == [out.stderr.strip()] and "camera 97" in out.stderr
    assert list(tmp_path.iterdir()) == []


# --- a parser that imports nothing heavy ---------------------------------------------------------


def test_building_the_parser_imports_neither_torch_nor_sklearn():
    # the cause of a slow --help: what building the parser and the help texts import
    # (reproduce --help lists the --set keys, strategies and quick changes: sklearn_hardness._experiment_names)
    code = ("import sys, contextlib, io, sklearn_hardness._cli as c\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    for argv in (['--help'], ['--version'], ['reproduce', '--help'], ['evaluate', '--help']):\n"
            "        try:\n"
            "            c.main(argv)\n"
            "        except SystemExit:\n"
            "            pass\n"
            "print(sorted(m for m in ('torch', 'skorch', 'sklearn', 'numpy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_names_offered_by_the_parser_are_the_library_s():
    from sklearn_hardness._cli import build_parser
    from sklearn_hardness._cli._common import _SIM_PRESETS
    from sklearn_hardness.datasets._sim_presets import PRESETS
    from sklearn_hardness.experiments._models import MODEL_NAMES, make_estimator
    from sklearn_hardness.model_selection import evaluate_pipelines
    from sklearn_hardness.models import make_named_pipeline

    def choices(command, dest):
        sub = next(a for a in build_parser()._actions if a.dest == "command").choices[command]
        action = next(a for a in sub._actions if a.dest == dest)
        return tuple(action.choices), action.default

    assert set(_SIM_PRESETS) == set(PRESETS)
    pipelines, default = choices("evaluate", "pipelines")
    assert all(make_named_pipeline(name) is not None for name in pipelines)  # every name the parser offers builds
    with pytest.raises(ValueError, match="unknown pipeline"):
        evaluate_pipelines(["not-a-pipeline"], [], [])
    assert default is None  # evaluate_pipelines' default: DEFAULT_PIPELINES, + loading_compliance with force
    from sklearn_hardness.models import pipeline_info, pipeline_names

    DEFAULT_PIPELINES = [n for n in pipeline_names() if pipeline_info(n).default]
    PIPELINE_NAMES = pipeline_names()

    assert pipelines == PIPELINE_NAMES

    assert set(DEFAULT_PIPELINES) <= set(pipelines) and "peak_change" not in DEFAULT_PIPELINES  # baseline: always
    models, _ = choices("reproduce", "model")
    assert tuple(models) == tuple(MODEL_NAMES)
    from sklearn_hardness.experiments import get_config

    assert all(make_estimator(m, get_config(), 0, 3) is not None for m in MODEL_NAMES)


def test_every_set_key_is_documented_in_help_and_docstring(capsys):
    from sklearn_hardness.experiments import CONFIG_KEYS, get_config

    keys = set(get_config("silicone5")) - {"preset"}
    assert set(CONFIG_KEYS) == keys
    with pytest.raises(SystemExit):
        main(["reproduce", "--help"])
    text = capsys.readouterr().out
    for key in keys:
        assert f"``{key}``" in get_config.__doc__
        assert f"\n  {key} " in text, key
    assert "variance entropy random bald" in " ".join(text.split())  # the strategies, filled in when help is shown
    for sub in ("select", "record", "simulate", "evaluate", "cache"):
        with pytest.raises(SystemExit):
            main([sub, "--help"])
        assert "--quiet" in capsys.readouterr().out


@pytest.mark.parametrize("command", ["select", "record", "simulate", "reproduce", "evaluate", "cache"])
def test_every_option_has_help(command):
    from sklearn_hardness._cli import build_parser

    argv = {"select": ["m.csv"], "record": ["--label", "a", "--out", "o"], "simulate": ["--out", "o"],
            "evaluate": ["everyday"]}.get(command, [])
    parser = build_parser().parse_args([command, *argv])._command_parser
    assert all(action.help for action in parser._actions), command


# --- select: machine-readable output ------------------------------------------------------------


def test_select_roi_finds_contact_on_the_gel(tmp_path, capsys):
    """``select --roi``: where the rest of the frame brightens, contact is found where the gel alone shows it."""
    import json

    import numpy as np

    from sklearn_hardness.io import write_video
    from sklearn_hardness.preprocessing import ContactFrameSelector

    from ._synthetic import FRAMED_GEL, framed_press, growing_disc_press

    rng = np.random.default_rng(3)
    rows, gels = ["path,label,object_id"], []
    for i in range(4):
        video = framed_press(growing_disc_press(int(rng.integers(2, 30)), 8.0, rng), rng)
        write_video(tmp_path / f"p{i}.avi", video)
        rows.append(f"p{i}.avi,{'soft' if i % 2 else 'hard'},o{i}")
        gels.append(video[:, 8:40, 16:48])
    (tmp_path / "manifest.csv").write_text("\n".join(rows) + "\n")
    starts = {}
    for roi in ([], ["--roi", *map(str, FRAMED_GEL)]):
        assert main(["select", str(tmp_path / "manifest.csv"), "--format", "json", "--quiet", *roi]) == 0
        starts[bool(roi)] = [r["start"] for r in json.loads(capsys.readouterr().out)]
    on_gel = ContactFrameSelector(on_no_contact="fallback").select(gels).contact_start.tolist()
    assert starts[True] == on_gel != starts[False]


def test_select_writes_json_and_csv(tmp_path, capsys):
    import csv
    import json

    manifest, _ = _write_dataset(tmp_path)
    assert main(["select", str(manifest), "--format", "json", "--quiet"]) == 0
    captured = capsys.readouterr()
    records = json.loads(captured.out)
    assert captured.err == ""
    assert len(records) == 6 and records[0]["label"] == "soft" and records[0]["contact_found"] is True
    assert all(len(r["selected"]) == 4 for r in records)  # first, last and 2 between
    assert main(["select", str(manifest), "--output", str(tmp_path / "sel.csv")]) == 0
    assert capsys.readouterr().out == ""  # the records went to the file, the summary to stderr
    with open(tmp_path / "sel.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["label"] for r in rows] == [r["label"] for r in records]
    assert rows[0]["selected"] == " ".join(map(str, records[0]["selected"]))


def test_a_one_frame_press_is_named_by_its_file_in_select_and_the_experiments(tmp_path, capsys):
    # the selection needs two frames; the error says which press of the manifest, not which of a chunk
    from sklearn_hardness.datasets import load_press_videos
    from sklearn_hardness.experiments._data import _select_frames
    from sklearn_hardness.io import read_video, write_video

    manifest, _ = _write_dataset(tmp_path, n_per_class=20)
    data = load_press_videos(manifest)
    cut = data.paths[37]
    write_video(cut, read_video(cut)[:1])
    with pytest.raises(SystemExit, match="2"):
        main(["select", str(manifest)])
    assert f"X[37] ({cut}) has 1 frame(s); at least 2 are needed" in capsys.readouterr().err
    params = dict(output_size=(8, 10), n_between=2, color="gray", subtract_first=True)
    with pytest.raises(ValueError, match=rf"^press 37 \({cut}\) has 1 frame\(s\)"):  # 37 is X[5] of its chunk
        _select_frames(load_press_videos(manifest).videos, params, verbose=False)
