"""
Simulated GelSight presses: what the camera sees and the mechanics behind it
============================================================================

:func:`sklearn_hardness.datasets.make_presses` simulates the paper's robot
dataset (``silicone5``): five silicone objects of compliance 0.44 to
1.13 mm/N pressed by a GelSight Mini. This example shows one press per
object at its deepest frame, and the mechanics of many presses: the contact
radius and the gel's own indentation against the force.

The gel's indentation depends on the force only (gel and object are springs
in series carrying the same force), so image intensity and depth alone are
confounded with how hard the robot pushed. The contact radius follows the
*total* approach of gel and object, so at the same force a softer object
gives a larger contact: the hardness lives in the relation between the two.
"""

# %%
# One press per object
# --------------------
# Top row: the frame of maximum force. Bottom row: its difference to the
# first frame (grey = no change), which is what ContactFrameSelector works on.
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from sklearn_hardness.datasets import make_presses

data = make_presses("silicone5", n_per_class=1, random_state=0, force_range=(3, 3))
fig, axes = plt.subplots(2, 5, figsize=(13, 4.2))
for k in range(5):
    i = int(np.flatnonzero(data.target == k)[0])
    video = data.videos[i]
    t = int(np.argmax(data.force[i]))
    diff = np.clip(video[t].astype(int) - video[0] + 128, 0, 255).astype(np.uint8)
    axes[0, k].imshow(video[t])
    axes[0, k].set_title(f"{data.target_names[k]} {data.hardness_unit}\nF = {data.force[i][t]:.1f} N")
    axes[1, k].imshow(diff)
for ax in axes.ravel():
    ax.set_axis_off()
fig.tight_layout()

# %%
# Contact radius and gel indentation against force
# ------------------------------------------------
# Per-frame mechanics of 20 presses per object (``return_mechanics=True``;
# the videos are never rendered here, so this is fast). Lines: the model's
# laws ``a = sqrt(R (c_g + c_o) F^(2/3))`` and ``delta_g = c_g F^(2/3)``.
mech = make_presses("silicone5", n_per_class=20, image_size=(48, 64), random_state=1,
                    return_mechanics=True)
colors = plt.cm.viridis(np.linspace(0, 0.9, 5))
fig, (ax_a, ax_g) = plt.subplots(1, 2, figsize=(11, 4))
force_grid = np.linspace(0, 7, 100)
c_gel = mech.press_params["compliance_gel"][0]
radius = mech.press_params["dome_radius"][0]
for k in range(5):
    for i in np.flatnonzero(mech.target == k):
        m = mech.mechanics[i]
        on = m["force_true"] > 0
        ax_a.plot(m["force_true"][on], m["contact_radius"][on], ".", color=colors[k], ms=3)
        ax_g.plot(m["force_true"][on], m["gel_indentation"][on], ".", color=colors[k], ms=3)
    c_obj = mech.hardness[k]
    ax_a.plot(force_grid, np.sqrt(radius * (c_gel + c_obj) * force_grid ** (2 / 3)),
              color=colors[k], label=f"{mech.target_names[k]} mm/N")
ax_g.plot(force_grid, c_gel * force_grid ** (2 / 3), "k-", lw=1, label="gel law (all objects)")
ax_a.set(xlabel="force (N)", ylabel="contact radius (mm)", title="contact radius grows with total approach")
ax_g.set(xlabel="force (N)", ylabel="gel indentation (mm)", title="gel indentation: the same for every object")
ax_a.legend(title="object compliance")
ax_g.legend()
fig.tight_layout()

# %%
# The press in time
# -----------------
# Force of one press per object against time: approach, the stop triggered
# by the lagged force estimate (the true force overshoots ``F_push``, dashed),
# and the retreat. Dots mark the video frames.
fig, ax = plt.subplots(figsize=(7, 3.5))
for k in range(5):
    i = int(np.flatnonzero(mech.target == k)[0])
    m = mech.mechanics[i]
    ax.plot(m["time"], m["force_true"], "o-", ms=3, color=colors[k], label=mech.target_names[k])
    ax.axhline(mech.press_params["F_push"][i], color=colors[k], ls="--", lw=0.8)
ax.set(xlabel="time (s)", ylabel="force (N)")
ax.legend(title="mm/N", fontsize=8)
fig.tight_layout()
