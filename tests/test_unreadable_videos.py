"""Videos that cannot be read: one error lists every one of them, before any fit.

A pass over every press stops at the first video it cannot read; a user
mending a manifest of hundreds of recordings wants them all at once, and
``evaluate`` used to go on to fit every fold and print a table of NaN.
"""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

from sklearn_hardness._cli import main
from sklearn_hardness.datasets import load_press_videos
from sklearn_hardness.model_selection import evaluate_pipelines
from sklearn_hardness.utils._lazy import LazyVideoSequence
from sklearn_hardness.utils._unreadable import UnreadableVideosError, raise_unreadable

from ._exp_data import tiny_presses, write_object_manifest

_BAD = {3: "corrupt.avi", 12: "truncated.npy"}  # press index -> the file that replaces its video


@pytest.fixture(scope="module")
def manifest(tmp_path_factory):
    """20 presses of 10 objects (5 classes, 2 objects each); two files cannot be read."""
    folder = tmp_path_factory.mktemp("recordings")
    manifest = write_object_manifest(folder, tiny_presses(n_per_class=4), presses_per_object=2, paths=_BAD)
    (folder / "corrupt.avi").write_bytes(os.urandom(2048))
    (folder / "truncated.npy").write_bytes((folder / "press_000.npy").read_bytes()[:150])
    return manifest


def _assert_lists_both(text):
    assert "2 of 20 videos cannot be read" in text
    assert "video 3: " in text and "corrupt.avi" in text
    assert "video 12: " in text and "truncated.npy" in text
    assert "Remove their rows from the manifest" in text


def _loader(key):
    if key % 3 == 1:
        raise ValueError(f"cannot decode {key}")
    return np.zeros((2, 4, 4, 3), np.uint8)


def test_raise_unreadable_lists_every_video_that_cannot_be_read():
    cause = ValueError("the first one")
    with pytest.raises(UnreadableVideosError) as info:
        raise_unreadable(LazyVideoSequence(_loader, range(8)), cause)
    message = str(info.value)
    assert message.startswith("3 of 8 videos cannot be read")
    assert [line.strip() for line in message.splitlines()[1:4]] == [
        "video 1: cannot decode 1", "video 4: cannot decode 4", "video 7: cannot decode 7"]
    assert info.value.__cause__ is cause and isinstance(info.value, ValueError)
    # every video reads, or the videos are in memory: nothing to say, the caller re-raises its own error
    assert raise_unreadable(LazyVideoSequence(_loader, [0, 2, 3])) is None
    assert raise_unreadable([np.zeros((2, 4, 4, 3), np.uint8)]) is None


@pytest.mark.parametrize("error_score", ["raise", np.nan])
def test_evaluate_lists_the_unreadable_videos_before_any_fit(manifest, error_score):
    # before: the baseline's pass failed, every fold of every pipeline failed on the first bad video,
    # and (error_score=nan) the table was NaN with a recommendation drawn from it
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no "pipeline failed on a fold" warning
        with pytest.raises(UnreadableVideosError) as info:
            data = load_press_videos(manifest)
            evaluate_pipelines(["contact_profile"], data.videos, data.target, groups=data.object_id, cv=2,
                               target_names=data.target_names, error_score=error_score)
    _assert_lists_both(str(info.value))


@pytest.mark.parametrize("command", [
    ["select"],
    ["evaluate", "--pipelines", "contact_profile", "--cv", "2", "--quiet"],
], ids=["select", "evaluate"])
def test_cli_names_every_unreadable_video_in_one_error(manifest, tmp_path, capsys, command):
    args = command[:1] + [str(manifest)] + command[1:]
    if command[0] == "evaluate":
        args += ["--out", str(tmp_path / "out")]
    with pytest.raises(SystemExit, match="2"):
        main(args)
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "Traceback" not in err
    _assert_lists_both(err)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("model", ["contact_profile", "ofnn"])  # whole-video features; selected frames
def test_reproduce_names_every_unreadable_video_before_any_run(manifest, tmp_path, capsys, model):
    out = tmp_path / "out"
    with pytest.raises(SystemExit, match="2"):
        main(["reproduce", "--dataset", str(manifest), "--model", model, "--quick", "--out", str(out),
              "--quiet"])
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "Traceback" not in err
    _assert_lists_both(err)
    assert not (out / "results.jsonl").exists()
