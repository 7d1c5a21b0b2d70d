"""
=======================================
Optical-flow features drawn on a press
=======================================

The OFNN model of the paper (Sec. II-B) does not look at pixels: it sees the
displacements of the strongest Shi-Tomasi corners, tracked with pyramidal
Lucas-Kanade through the selected contact frames.
:class:`~sklearn_hardness.features.OpticalFlowFeatures` computes them, and its
:meth:`~sklearn_hardness.features.OpticalFlowFeatures.track` method returns
the raw tracks, so we can draw what the classifier actually receives.

We compare a soft and a hard object of the simulated ``silicone5`` set: the
question is whether the tracks differ in a way a small network can pick up.
"""

# %%
# Two presses: the softest and the hardest object
# -----------------------------------------------
# Raw frames (``subtract_first=False``) so that the corners are the gel's
# markers and texture, as on a real sensor.
import matplotlib.pyplot as plt
import numpy as np

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.features import OpticalFlowFeatures
from sklearn_hardness.preprocessing import ContactFrameSelector

data = make_presses("silicone5", n_per_class=2, image_size=(120, 160),
                    random_state=0)
soft = int(np.flatnonzero(data.target == np.argmax(data.hardness))[0])
hard = int(np.flatnonzero(data.target == np.argmin(data.hardness))[0])
selector = ContactFrameSelector(n_between=2, subtract_first=False)
frames = selector.fit_transform([data.videos[soft], data.videos[hard]])
print("selected frames:", frames.shape, "(presses, k, H, W, C)")

# %%
# Track the corners
# -----------------
# ``transform`` gives one flat vector per press (the OFNN input);
# ``track`` gives the positions behind it, with a mask of the tracks kept.
flow = OpticalFlowFeatures(n_features=80).fit(frames)
features = flow.transform(frames)
tracks = flow.track(frames)
print("feature vector per press:", features.shape[1], "values")
print("corners found:", tracks.n_corners.tolist())
# Displacement of each tracked corner against the first frame; corners
# never found (zero padding) or lost are left out of the means.
moved = np.linalg.norm(tracks.points - tracks.points[:, :, :1], axis=-1)
moved = np.where(tracks.valid, moved, np.nan)  # (2 presses, n_features, k)
at_peak = np.nanmean(moved[:, :, -1], axis=1)
print(f"mean |displacement| at peak (px): soft {at_peak[0]:.2f}, hard {at_peak[1]:.2f}")

# %%
# The tracks on the last selected frame (peak deformation)
# --------------------------------------------------------
# Each line runs from a corner in the first contact frame to where
# Lucas-Kanade found it at the peak; arrows are magnified so that
# sub-pixel motion is visible.
scale = 3.0
fig, axes = plt.subplots(1, 2, figsize=(10, 4))
for ax, i, name in zip(axes, range(2), ["softest", "hardest"]):
    target = data.target[[soft, hard][i]]
    ax.imshow(frames[i, -1])
    ok = tracks.valid[i, :, -1]
    start = tracks.points[i, ok, 0]
    end = tracks.points[i, ok, -1]
    u, v = (scale * (end - start)).T
    ax.quiver(start[:, 0], start[:, 1], u, v, color="yellow",
              angles="xy", scale_units="xy", scale=1, width=0.004)
    hardness = f"{data.hardness[target]:.2f} {data.hardness_unit}"
    ax.set_title(f"{name}: {hardness}, {ok.sum()} tracks")
    ax.axis("off")
fig.suptitle(f"Corner displacements from first contact to peak (x{scale:g})")
fig.tight_layout()

# %%
# Displacement over the selected frames
# -------------------------------------
# The mean displacement per frame is one summary of what the OFNN sees; the
# network gets every corner's ``(dx, dy)``, ordered by corner strength.
fig, ax = plt.subplots(figsize=(6, 3.5))
for i, name in enumerate(["softest", "hardest"]):
    mean_moved = np.nanmean(moved[i, :, 1:], axis=0)
    ax.plot(range(1, frames.shape[1]), mean_moved, "o-", label=name)
ax.set_xlabel("selected frame (after the first)")
ax.set_ylabel("mean |displacement| (px)")
ax.set_xticks(range(1, frames.shape[1]))
ax.legend()
fig.tight_layout()
plt.show()
