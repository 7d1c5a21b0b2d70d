"""
===============================================
Selecting the loading period of tactile presses
===============================================

The paper (Sec. II-A) feeds its classifiers only the *loading period* of a
press: from the first frame of contact to the frame of maximum deformation.
:class:`~sklearn_hardness.preprocessing.ContactFrameSelector` finds it from the
mean intensity change against the first frame, with a threshold that adapts
to each video's noise, and keeps the first and last frame plus ``n_between``
frames at equal spacing. Weak contacts in compressed streams (real marker-less
GelSight Mini presses of soft objects) are found by a second, localised test;
the last section shows one.

Here we run it on simulated GelSight Mini presses of the paper's five
silicone objects and plot the contact curves with the chosen frames, next to
the robot's force, and the selected frames of one press.
"""

# %%
# Simulated presses
# -----------------
import matplotlib.pyplot as plt
import numpy as np

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.preprocessing import ContactFrameSelector, plot_contact_selection

data = make_presses("silicone5", n_per_class=3, image_size=(120, 160), random_state=0)
print(f"{len(data.videos)} presses, {len(data.videos[0])} frames each at 25 fps")

# %%
# Select the contact frames
# -------------------------
selector = ContactFrameSelector(n_between=2)
frames = selector.fit_transform(data.videos)
selection = selector.selection_
print("frames:", frames.shape, frames.dtype)
print("contact found in", selection.contact_found.sum(), "of", len(selection.contact_found), "presses")

# %%
# Contact curves, with the force the robot measured
# ---------------------------------------------------
labels = [f"{data.hardness[t]:.2f} {data.hardness_unit}" for t in data.target]
fig, (ax0, ax1) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
plot_contact_selection(selection, labels=labels, timestamps=data.timestamps, ax=ax0)
for i in range(len(data.videos)):
    ax1.plot(data.timestamps[i], data.force[i], color="0.5", lw=0.8)
    ax1.plot(data.timestamps[i][selection.indices[i]], data.force[i][selection.indices[i]], "o", ms=3)
ax1.set_xlabel("time (s)")
ax1.set_ylabel("force (N)")
ax1.set_title("Robot force; dots: selected frames")
fig.tight_layout()

# %%
# The selected frames of one press
# --------------------------------
# With ``subtract_first=True`` (the default) the output is the change against
# the first frame, in [-1, 1]; we show the raw frames next to it.
i = 0
raw = ContactFrameSelector(n_between=2, subtract_first=False).fit_transform(data.videos[i : i + 1])[0]
fig, axes = plt.subplots(2, frames.shape[1], figsize=(10, 4))
for j in range(frames.shape[1]):
    axes[0, j].imshow(raw[j])
    axes[0, j].set_title(f"frame {selection.indices[i][j]}")
    axes[1, j].imshow(np.clip(0.5 + 2 * frames[i, j], 0, 1))
    for ax in axes[:, j]:
        ax.axis("off")
axes[1, 0].set_title("change x2", loc="left")
fig.suptitle(f"Press 0: object {labels[i]}")
fig.tight_layout()

# %%
# A weak contact in a compressed stream
# -------------------------------------
# Real marker-less presses of soft objects change the picture by only a grey
# level or two, and an H.264/mp4 stream adds its own noise: the mean change
# rises over the first frames as the codec settles and dips at key frames.
# Here a faint sharp edge (a hard object's rim) is pressed into a flat gel
# from frame 20 and the video goes through the lossy ``mp4v`` codec. The mean
# curve hardly moves; the selector's second test, on the most-changed cells
# of the pad, finds the contact (``status`` says which test did). The codec
# delivers a faint change in steps, at its key frames (every 12 frames for
# ``mp4v``), so the decoded video, and the peak found on it, can lag the press.
import os
import tempfile

from sklearn_hardness.io import read_video, write_video

rng = np.random.default_rng(0)
yy, xx = np.mgrid[:64, :96]
edge = np.exp(-(((yy - 32 - 0.3 * (xx - 48)) / 1.5) ** 2))[..., None] * np.array([8.0, 4.0, -6.0])
load = np.clip((np.arange(64) - 20) / 8, 0, 1)[:, None, None, None]
raw = np.clip(110 + load * edge + rng.normal(0, 0.8, (64, 64, 96, 3)), 0, 255).astype(np.uint8)
path = os.path.join(tempfile.mkdtemp(), "faint.mp4")
write_video(path, raw)
weak = ContactFrameSelector(n_between=2).select([read_video(path)])
print("status:", weak.status[0], "start", weak.contact_start[0], "peak", weak.contact_peak[0])
fig = plot_contact_selection(weak, labels=["faint edge, mp4v"])
fig.axes[0].axvline(20, color="0.5", ls=":", label="first touch")
fig.axes[0].axvline(28, color="0.5", ls="--", label="full load")
fig.axes[0].legend()
plt.show()
