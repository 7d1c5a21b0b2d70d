import warnings

import numpy as np
import pytest
from sklearn.model_selection import train_test_split

from sklearn_hardness.datasets import load_press_videos
from sklearn_hardness.io import write_video
from sklearn_hardness.utils._lazy import LazyVideoSequence

from ._synthetic import synthetic_press


def _write_dataset(root, n_per_class=3, labels=("soft", "hard"), hardness=(1.13, 0.44)):
    rows = ["path,label,hardness,hardness_unit,object_id,force_path,timestamps_path,position_path,fps,operator"]
    videos = []
    for c, (label, h) in enumerate(zip(labels, hardness)):
        for j in range(n_per_class):
            video = synthetic_press(n_frames=12 + j, size=(16, 20), contact_start=4, peak=8, seed=10 * c + j)
            name = f"videos/{label}_{j}.avi"
            write_video(root / name, video)
            np.save(root / f"videos/{label}_{j}_force.npy", np.linspace(0, 3, len(video)))
            (root / f"videos/{label}_{j}_t.txt").write_text("\n".join(str(t / 25) for t in range(len(video))))
            np.save(root / f"videos/{label}_{j}_z.npy", h * np.linspace(0, 3, len(video)) ** (2 / 3))
            rows.append(
                f"{name},{label},{h},mm/N,{label}-cast{j % 2},videos/{label}_{j}_force.npy,"
                f"videos/{label}_{j}_t.txt,videos/{label}_{j}_z.npy,25,alice"
            )
            videos.append(video)
    (root / "manifest.csv").write_text("\n".join(rows) + "\n")
    return root / "manifest.csv", videos


def test_load_round_trip(tmp_path):
    manifest, videos = _write_dataset(tmp_path)
    data = load_press_videos(manifest)
    assert isinstance(data.videos, LazyVideoSequence)
    assert len(data.videos) == 6
    assert data.target_names.tolist() == ["hard", "soft"]  # sorted labels
    assert data.target.tolist() == [1, 1, 1, 0, 0, 0]
    np.testing.assert_allclose(data.hardness, [0.44, 1.13])
    assert data.hardness_unit == "mm/N"
    for i, video in enumerate(videos):
        np.testing.assert_array_equal(data.videos[i], video)  # FFV1 is lossless
        assert len(data.force[i]) == len(video) and len(data.timestamps[i]) == len(video)
        np.testing.assert_array_equal(data.position[i], np.load(data.paths[i].with_name(f"{data.paths[i].stem}_z.npy")))
    assert data.object_id[0] == "soft-cast0"
    assert data.metadata == {"operator": ["alice"] * 6}
    np.testing.assert_allclose(data.fps, 25)


def test_loading_is_lazy(tmp_path, monkeypatch):
    manifest, _ = _write_dataset(tmp_path)
    calls = []
    import sklearn_hardness.io._video as video_mod

    real = video_mod.read_video
    monkeypatch.setattr("sklearn_hardness.datasets._manifest.read_video", lambda p: calls.append(p) or real(p))
    data = load_press_videos(manifest)
    assert calls == []
    train, test, y_train, y_test = train_test_split(
        data.videos, data.target, test_size=2, stratify=data.target, random_state=0
    )
    assert isinstance(train, LazyVideoSequence) and len(train) == 4
    assert calls == []  # splitting decodes nothing
    test[0]
    assert len(calls) == 1


def test_numeric_labels_sort_numerically(tmp_path):
    manifest, _ = _write_dataset(tmp_path, labels=("10", "9"), hardness=(1, 2))
    data = load_press_videos(manifest)
    assert data.target_names.tolist() == ["9", "10"]


def test_missing_files_are_all_listed(tmp_path):
    manifest, _ = _write_dataset(tmp_path)
    (tmp_path / "videos/soft_0.avi").unlink()
    (tmp_path / "videos/hard_2.avi").unlink()
    (tmp_path / "videos/hard_1_force.npy").unlink()
    (tmp_path / "videos/soft_2_z.npy").unlink()
    with pytest.raises(FileNotFoundError) as exc:
        load_press_videos(manifest)
    msg = str(exc.value)
    assert "4 missing" in msg
    for name in ("soft_0.avi", "hard_2.avi", "hard_1_force.npy", "soft_2_z.npy"):
        assert name in msg


def test_manifest_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="Manifest not found"):
        load_press_videos(tmp_path / "none.csv")
    bad = tmp_path / "bad.csv"
    bad.write_text("file,class\na.avi,1\n")
    with pytest.raises(ValueError, match="lacks required column"):
        load_press_videos(bad)
    bad.write_text("path,label\n")
    with pytest.raises(ValueError, match="lists no videos"):
        load_press_videos(bad)
    manifest, _ = _write_dataset(tmp_path)
    text = manifest.read_text().splitlines()
    text[1] = text[1].replace(",1.13,", ",0.9,")
    manifest.write_text("\n".join(text))
    with pytest.raises(ValueError, match="one hardness value"):
        load_press_videos(manifest)
    text[1] = text[1].replace(",0.9,", ",soft,")
    manifest.write_text("\n".join(text))
    with pytest.raises(ValueError, match="'hardness' must be a number"):
        load_press_videos(manifest)


def test_lazy_sequence_indexing():
    seq = LazyVideoSequence(lambda k: np.full((2, 3, 3, 3), k, np.uint8), range(5))
    assert seq.shape == (5,)
    assert int(seq[-1][0, 0, 0, 0]) == 4
    assert [int(v[0, 0, 0, 0]) for v in seq[np.array([True, False, True, False, False])]] == [0, 2]
    assert len(seq[1:4]) == 3
    with pytest.raises(IndexError):
        seq[5]
    with pytest.raises(IndexError):
        seq[np.array([[0, 1]])]


_CALLS = []


def _loader(k):
    _CALLS.append(k)
    return np.full((2, 3, 3, 3), k, np.uint8)


def test_lazy_sequence_cache_and_pickle():
    import pickle

    _CALLS.clear()
    seq = LazyVideoSequence(_loader, range(3), cache_size=2)
    seq[0], seq[0], seq[1], seq[0]
    assert _CALLS == [0, 1]  # the second and third access of video 0 hit the cache
    seq[2]  # evicts video 1, the least recently used
    seq[1]
    assert _CALLS == [0, 1, 2, 1]
    clone = pickle.loads(pickle.dumps(seq))
    assert clone._cache == {} and clone[2].shape == (2, 3, 3, 3)


def test_labels_that_differ_only_in_case_are_named(tmp_path):
    manifest, _ = _write_dataset(tmp_path, labels=("soft", "Soft", "hard"), hardness=(1.13, 1.13, 0.44))
    with pytest.warns(UserWarning, match="labels 'Soft' and 'soft' differ only in case") as record:
        data = load_press_videos(manifest)
    assert record[0].filename == __file__  # points at the caller's line
    assert data.target_names.tolist() == ["Soft", "hard", "soft"]  # kept as written: three classes
    (tmp_path / "clean").mkdir()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # labels written one way: no warning
        load_press_videos(_write_dataset(tmp_path / "clean")[0])


def test_an_object_has_one_label_and_ids_are_given_on_every_row_or_none(tmp_path):
    manifest, _ = _write_dataset(tmp_path)
    text = manifest.read_text().splitlines()  # ids soft-cast0, soft-cast1, soft-cast0, hard-cast0, ...
    # objects numbered within each label ("cast0" soft and "cast0" hard) would be one object to the folds
    numbered = [line.replace("soft-cast", "cast").replace("hard-cast", "cast") for line in text]
    manifest.write_text("\n".join(numbered) + "\n")
    with pytest.raises(ValueError, match=r"object_id 'cast0' has presses labelled 'soft' \(line 2\), 'hard' "
                                         r"\(line 5\) \(and 1 other object_id\(s\) likewise\).*e\.g\. 'soft-cast0'"):
        load_press_videos(manifest)
    # a blank id among given ones would merge the unknown objects of a label into one
    blank = list(text)
    blank[3] = blank[3].replace(",soft-cast0,", ",,")
    manifest.write_text("\n".join(blank) + "\n")
    with pytest.raises(ValueError, match=r"'object_id' is empty on line\(s\) 4 while other rows give it"):
        load_press_videos(manifest)
    # no id on any row: every label is one object, as documented
    none = [",".join(c if i != 4 else "" for i, c in enumerate(line.split(","))) for line in text[1:]]
    manifest.write_text("\n".join([text[0], *none]) + "\n")
    data = load_press_videos(manifest)
    assert data.object_id.tolist() == np.asarray(data.target_names)[data.target].tolist()


def test_errors_name_the_file_line_past_empty_rows(tmp_path):
    manifest, _ = _write_dataset(tmp_path)
    text = manifest.read_text().splitlines()
    n_cols = text[0].count(",")
    text.insert(2, "," * n_cols)  # a row of empty cells, as spreadsheets export them: not a press
    text[4] = text[4].replace(",soft,", ",,", 1)  # file line 5
    manifest.write_text("\n".join(text) + "\n")
    with pytest.raises(ValueError, match="line 5: empty 'label'"):
        load_press_videos(manifest)


def test_manifest_cells_beyond_the_header_encoding_and_fps_are_checked(tmp_path):
    # what a spreadsheet or a hand-edited file gives: nothing is dropped or misread silently
    write_video(tmp_path / "a.avi", np.zeros((4, 16, 16, 3), np.uint8))
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("path,label\na.avi,soft,extra\n")  # an unquoted comma in a cell, or no column name
    with pytest.raises(ValueError, match=r"line 2 has more cells than the header's 2 columns \(\['extra'\]"):
        load_press_videos(manifest)
    manifest.write_text("path,label,,\na.avi,soft,,\n")  # empty trailing cells are no data
    assert load_press_videos(manifest).target_names.tolist() == ["soft"]
    manifest.write_bytes("path,label\na.avi,d\xe9j\xe0 vu\n".encode("cp1252"))  # Excel's "CSV" on Windows
    with pytest.raises(ValueError, match=r"manifest.csv' is not UTF-8 text \(byte 18.*CSV UTF-8"):
        load_press_videos(manifest)
    for fps in ("0", "-5"):
        manifest.write_text(f"path,label,fps\na.avi,soft,{fps}\n")
        with pytest.raises(ValueError, match=r"line 2: column 'fps' must be positive"):
            load_press_videos(manifest)


def test_a_per_frame_series_saved_as_a_table_is_an_error(tmp_path):
    # a (time, force) export read as one series interleaved time and force values
    write_video(tmp_path / "a.avi", np.zeros((4, 16, 16, 3), np.uint8))
    np.savetxt(tmp_path / "force.csv", np.column_stack([np.arange(4) / 25, np.linspace(0, 3, 4)]), delimiter=",")
    np.save(tmp_path / "column.npy", np.linspace(0, 3, 4)[:, None])  # one column: a series
    (tmp_path / "manifest.csv").write_text("path,label,force_path,position_path\na.avi,soft,force.csv,column.npy\n")
    with pytest.raises(ValueError, match=r"force.csv' holds a table of shape \(4, 2\); a per-frame series"):
        load_press_videos(tmp_path / "manifest.csv")
    (tmp_path / "manifest.csv").write_text("path,label,force_path,position_path\na.avi,soft,column.npy,column.npy\n")
    assert load_press_videos(tmp_path / "manifest.csv").force[0].shape == (4,)
