import os

import numpy as np
import pytest

from sklearn_hardness.io import read_video, write_video


@pytest.fixture
def frames():
    rng = np.random.default_rng(0)
    return rng.integers(0, 256, size=(7, 24, 32, 3), dtype=np.uint8)


@pytest.mark.parametrize("ext", [".avi", ".mkv", ".npy", ""])
def test_lossless_round_trip(tmp_path, frames, ext):
    path = tmp_path / f"press{ext}"
    write_video(path, frames, fps=25)
    out = read_video(path)
    assert out.dtype == np.uint8 and out.shape == frames.shape
    np.testing.assert_array_equal(out, frames)


def test_mp4_is_lossy_but_close_on_smooth_frames(tmp_path):
    yy, xx = np.mgrid[:48, :64]
    base = np.stack([xx * 3, yy * 4, np.full_like(xx, 128)], -1).astype(np.uint8)
    frames = np.stack([np.roll(base, t, axis=1) for t in range(6)])
    write_video(tmp_path / "p.mp4", frames, fps=25)
    out = read_video(tmp_path / "p.mp4")
    assert out.shape == frames.shape
    assert np.abs(out.astype(int) - frames).mean() < 8


def test_rgb_order_is_kept(tmp_path):
    frames = np.zeros((2, 16, 16, 3), np.uint8)
    frames[..., 0] = 200  # pure red
    write_video(tmp_path / "red.avi", frames)
    out = read_video(tmp_path / "red.avi")
    assert out[..., 0].min() == 200 and out[..., 1:].max() == 0


def test_image_folder_sorted_numerically(tmp_path, frames):
    import cv2

    folder = tmp_path / "frames"
    folder.mkdir()
    for t in range(len(frames)):
        # names whose lexicographic order differs from numeric order
        cv2.imwrite(str(folder / f"img_{t + 1}.png"), cv2.cvtColor(frames[t], cv2.COLOR_RGB2BGR))
    (folder / "notes.txt").write_text("ignored")
    out = read_video(folder)
    np.testing.assert_array_equal(out, frames)


def test_max_frames(tmp_path, frames):
    write_video(tmp_path / "p.avi", frames)
    assert read_video(tmp_path / "p.avi", max_frames=3).shape[0] == 3


def test_grey_frames_are_written_as_rgb(tmp_path):
    grey = np.arange(4 * 8 * 8, dtype=np.uint8).reshape(4, 8, 8)
    write_video(tmp_path / "g.avi", grey)
    out = read_video(tmp_path / "g.avi")
    assert out.shape == (4, 8, 8, 3)
    np.testing.assert_array_equal(out[..., 1], grey)


def test_missing_file_names_path(tmp_path):
    with pytest.raises(FileNotFoundError, match="nope.mp4"):
        read_video(tmp_path / "nope.mp4")


def test_unreadable_file_names_path(tmp_path):
    path = tmp_path / "broken.mp4"
    path.write_bytes(b"this is not a video" * 10)
    with pytest.raises(ValueError, match="broken.mp4"):
        read_video(path)


def test_zero_frames(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match="no image files"):
        read_video(empty)
    path = tmp_path / "zero.avi"
    path.write_bytes(b"")
    with pytest.raises(ValueError, match="zero.avi"):
        read_video(path)


def test_folder_with_mixed_sizes(tmp_path):
    import cv2

    folder = tmp_path / "mixed"
    folder.mkdir()
    cv2.imwrite(str(folder / "0.png"), np.zeros((8, 8, 3), np.uint8))
    cv2.imwrite(str(folder / "1.png"), np.zeros((9, 8, 3), np.uint8))
    with pytest.raises(ValueError, match="same size"):
        read_video(folder)


def test_write_rejects_bad_input(tmp_path, frames):
    with pytest.raises(ValueError, match="extension"):
        write_video(tmp_path / "p.xyz", frames)
    with pytest.raises(ValueError, match="fps"):
        write_video(tmp_path / "p.avi", frames, fps=0)
    with pytest.raises(TypeError, match="uint8"):
        write_video(tmp_path / "p.avi", frames.astype(np.float32) / 255)
    with pytest.raises(ValueError, match="dimension"):
        write_video(tmp_path / "p.avi", frames[0, 0])
    with pytest.raises(ValueError, match="NaN"):
        bad = frames.astype(np.float32)
        bad[0, 0, 0, 0] = np.nan
        from sklearn_hardness.utils._validation import check_video

        check_video(bad)
    assert not os.path.exists(tmp_path / "p.avi")


def test_a_file_cut_short_is_an_error_not_a_shorter_video(tmp_path):
    # an interrupted recording or copy decodes as fewer frames than its header claims
    rng = np.random.default_rng(1)
    path = tmp_path / "press.avi"
    write_video(path, rng.integers(0, 256, size=(60, 24, 32, 3), dtype=np.uint8), fps=25)
    assert read_video(path).shape[0] == 60  # complete: as many frames as its header claims
    data = path.read_bytes()
    cut = tmp_path / "cut.avi"
    cut.write_bytes(data[: int(0.4 * len(data))])
    with pytest.raises(ValueError, match=r"cut.avi' decodes \d+ of the 60 frames its header claims"):
        read_video(cut)
    assert read_video(cut, max_frames=5).shape[0] == 5  # the frames asked for are there


def test_uint16_npy_is_read_as_uint8_by_its_high_byte(tmp_path, frames):
    # as 16-bit images are: the documented output is uint8 whatever the file holds
    path = tmp_path / "press16.npy"
    np.save(path, frames.astype(np.uint16) * 257)
    video = read_video(path)
    assert video.dtype == np.uint8
    np.testing.assert_array_equal(video, frames)
