import csv
import warnings

import numpy as np
import pytest

from sklearn_hardness._cli import main
from sklearn_hardness.datasets import load_press_videos
from sklearn_hardness.io import read_video, record_video, write_video
from sklearn_hardness.utils._param_validation import InvalidParameterError

from ._synthetic import synthetic_press


@pytest.fixture
def camera(tmp_path):
    """A lossless video file standing in for the camera, and its frames."""
    frames = synthetic_press(n_frames=30, size=(48, 64), contact_start=10, peak=18)
    path = tmp_path / "camera.avi"
    write_video(path, frames, fps=25)
    return path, frames


def test_record_from_a_file_source(camera, tmp_path):
    source, frames = camera
    out = record_video(source, n_frames=20)
    np.testing.assert_array_equal(out, frames[:20])  # FFV1: bit-exact, RGB order kept
    out = record_video(str(source), n_frames=10, warmup=5, path=tmp_path / "copy.avi")
    np.testing.assert_array_equal(out, frames[5:15])
    np.testing.assert_array_equal(read_video(tmp_path / "copy.avi"), frames[5:15])


def test_record_duration_and_size(camera):
    source, _ = camera
    assert record_video(source, duration=0.4, fps=25).shape[0] == 10
    assert record_video(source, n_frames=3, image_size=(24, 32)).shape == (3, 24, 32, 3)


def test_record_warns_when_the_source_ends_early(camera):
    source, frames = camera
    with pytest.warns(UserWarning, match="ended after 30 of 50 frames"):
        out = record_video(source, n_frames=50)
    np.testing.assert_array_equal(out, frames)
    with pytest.raises(ValueError, match="gave no frames"):
        record_video(source, n_frames=5, warmup=40)


def test_record_clear_errors(camera, tmp_path):
    source, _ = camera
    with pytest.raises(OSError, match="Could not open capture source camera 97"):
        record_video(97, n_frames=5)
    with pytest.raises(FileNotFoundError, match="not found"):
        record_video(tmp_path / "missing.mp4", n_frames=5)
    bad = tmp_path / "bad.mp4"
    bad.write_bytes(b"not a video")
    with pytest.raises(OSError, match="cannot decode"):
        record_video(bad, n_frames=5)
    with pytest.raises(ValueError, match="exactly one of n_frames and duration"):
        record_video(source)
    with pytest.raises(ValueError, match="exactly one of n_frames and duration"):
        record_video(source, n_frames=3, duration=1.0)
    with pytest.raises(InvalidParameterError, match="'n_frames'"):
        record_video(source, n_frames=0)
    with pytest.raises(InvalidParameterError, match="'source'"):
        record_video(1.5, n_frames=3)
    with pytest.raises(ValueError, match="image_size"):
        record_video(source, n_frames=3, image_size=(10,))


def test_cli_record_appends_to_a_manifest_that_loads(camera, tmp_path, capsys):
    source, frames = camera
    out = tmp_path / "presses"
    main(["record", "--source", str(source), "--label", "soft", "--out", str(out), "--n-frames", "30",
          "--object-id", "sponge 1", "--hardness", "1.5", "--hardness-unit", "rank"])
    printed = capsys.readouterr().out
    assert "contact selection: contact from frame" in printed
    main(["record", "--source", str(source), "--label", "hard", "--out", str(out), "--n-frames", "12",
          "--format", "npy", "--hardness", "3"])
    main(["record", "--source", str(source), "--label", "soft", "--out", str(out), "--n-frames", "30",
          "--object-id", "sponge 1"])
    with open(out / "manifest.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["label"] for r in rows] == ["soft", "hard", "soft"]
    assert rows[0]["path"] == "videos/soft_sponge_1_0000.avi" and rows[2]["path"] == "videos/soft_sponge_1_0001.avi"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no hardness conflict, no missing file
        data = load_press_videos(out / "manifest.csv")
    assert data.target_names.tolist() == ["hard", "soft"]
    assert data.target.tolist() == [1, 0, 1]
    assert data.object_id.tolist() == ["sponge 1", "hard", "sponge 1"]
    assert data.hardness.tolist() == [3.0, 1.5] and data.hardness_unit == "rank"  # taken over from row 1
    np.testing.assert_array_equal(data.videos[0], frames)
    np.testing.assert_array_equal(data.videos[1], frames[:12])


def test_cli_record_into_a_manifest_without_the_column(camera, tmp_path, capsys):
    source, _ = camera
    out = tmp_path / "presses"
    out.mkdir()
    (out / "manifest.csv").write_text("path,label\n")
    with pytest.raises(SystemExit, match="2"):
        main(["record", "--source", str(source), "--label", "soft", "--out", str(out), "--n-frames", "5"])
    assert "no column(s) ['object_id']" in capsys.readouterr().err
    assert not (out / "videos").exists()  # checked before recording: no orphan video, no empty folder
    assert (out / "manifest.csv").read_text() == "path,label\n"


def test_cli_record_keeps_hardness_consistent(camera, tmp_path, capsys):
    source, _ = camera
    out = tmp_path / "presses"
    args = ["record", "--source", str(source), "--out", str(out), "--n-frames", "5"]
    main(args + ["--label", "soft", "--hardness", "1"])
    with pytest.raises(SystemExit, match="2"):
        main(args + ["--label", "soft", "--hardness", "2"])
    assert "label 'soft' has hardness ['1'], not '2'" in capsys.readouterr().err
    with pytest.raises(SystemExit, match="2"):
        main(args + ["--label", "hard"])
    assert "pass --hardness for 'hard'" in capsys.readouterr().err
    assert len(list((out / "videos").iterdir())) == 1


def test_cli_record_without_a_camera(tmp_path, capsys):
    with pytest.raises(SystemExit, match="2"):
        main(["record", "--source", "97", "--label", "soft", "--out", str(tmp_path / "p")])
    assert "Could not open capture source camera 97" in capsys.readouterr().err
    assert not (tmp_path / "p").exists()


def test_simulated_sensor_streams_presses_of_the_chosen_object_through_record_video():
    from sklearn_hardness.datasets import SimulatedSensor, make_presses

    data = make_presses("everyday", n_per_class=2, n_objects=3, class_ratio=[1, 1, 1], image_size=(24, 32),
                        codec=None, random_state=0)
    sensor = SimulatedSensor(data, random_state=0)
    obj = sensor.objects[1]
    got = []
    for _ in range(3):  # two recorded presses of obj, then again in a new order
        sensor.press(obj)
        video = record_video(sensor, n_frames=sensor.n_frames)
        i = sensor.pressed_[-1][1]
        assert data.object_id[i] == obj
        np.testing.assert_array_equal(video, data.videos[i])  # RGB, as record_video returns a camera's
        assert sensor.n_frames == 0 and sensor.isOpened()  # left open: the next press reads on
        got.append(i)
    assert sorted(got[:2]) == np.flatnonzero(data.object_id == obj).tolist()
    with pytest.raises(ValueError, match="unknown object"):
        sensor.press("no-such-object")
    with pytest.raises(ValueError, match="gave no frames"):
        record_video(sensor, n_frames=5)  # nothing pressed since the last recording
    with pytest.raises(ValueError, match="object_id"):
        SimulatedSensor({"videos": data.videos})


def test_cli_record_refuses_an_object_id_recorded_with_another_label(camera, tmp_path, capsys):
    source, _ = camera
    out = tmp_path / "presses"
    args = ["record", "--source", str(source), "--out", str(out), "--n-frames", "5", "--object-id", "1"]
    main(args + ["--label", "soft"])
    with pytest.raises(SystemExit, match="2"):
        main(args + ["--label", "hard"])
    assert "object_id '1' is recorded with label 'soft', not 'hard'" in capsys.readouterr().err
    assert len(list((out / "videos").iterdir())) == 1  # checked before recording
    main(args[:-1] + ["hard-1", "--label", "hard"])
    assert load_press_videos(out / "manifest.csv").object_id.tolist() == ["1", "hard-1"]


def test_cli_record_of_one_frame_adds_no_row(tmp_path, capsys):
    source = tmp_path / "one.avi"
    write_video(source, synthetic_press(n_frames=30, size=(48, 64))[:1], fps=25)
    out = tmp_path / "presses"
    with pytest.raises(SystemExit, match="2"):
        main(["record", "--source", str(source), "--label", "soft", "--out", str(out), "--n-frames", "30"])
    err = capsys.readouterr().err
    assert "recorded 1 frame(s)" in err and "nothing was added to the manifest" in err
    assert not (out / "manifest.csv").exists() and not list((out / "videos").glob("*"))
