"""
Run time against error: how small can the frames be?
=====================================================

On a CPU the ConvLSTM's training time grows with the pixels of each selected
frame, and the accuracy learned from five presses per object does not always
grow with it. Here the same classifier is trained on the same presses at
three frame sizes; each is timed and scored on held-out presses of every
object, with the simplest baseline (one number per press and a logistic
regression) beside them.

``python benchmarks/bench_time_error.py`` measures the same trade-off for the
whole active-sampling protocol at the paper's settings, one knob at a time
(frame size, MC passes, epochs, threads), with its Pareto front.
"""

# %%
# Presses, split by press: five per object to train, the rest held out
# ---------------------------------------------------------------------
import time

import matplotlib.pyplot as plt
import numpy as np
import torch
from sklearn.linear_model import LogisticRegression
from sklearn.metrics import balanced_accuracy_score
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.features import PeakContactChange
from sklearn_hardness.models import ConvLSTMClassifier
from sklearn_hardness.preprocessing import ContactFrameSelector

# One torch thread: timings that do not depend on what else runs on the machine
# (two threads on two busy cores can be many times slower than one).
torch.set_num_threads(1)
data = make_presses("silicone5", n_per_class=15, image_size=(96, 128), random_state=0)
y = data.target
rng = np.random.default_rng(0)
train = np.concatenate([rng.choice(np.flatnonzero(y == c), 5, replace=False) for c in np.unique(y)])
test = np.setdiff1d(np.arange(len(y)), train)

# %%
# One classifier, three frame sizes
# ---------------------------------
rows = []
for size in [(6, 8), (12, 16), (24, 32)]:
    frames = ContactFrameSelector(n_between=2, frame_size=size, color="gray").fit_transform(data.videos)
    clf = ConvLSTMClassifier(max_epochs=60, random_state=0)
    t0 = time.perf_counter()
    clf.fit(frames[train], y[train])
    seconds = time.perf_counter() - t0
    error = 1 - balanced_accuracy_score(y[test], clf.predict(frames[test]))
    rows.append((f"{size[0]}x{size[1]}", seconds, error))
    print(f"frames {size[0]:>2}x{size[1]:<2}: fit {seconds:5.1f} s, held-out error {error:.2f}")

# %%
# The one-number baseline
# -----------------------
# The peak change of each press to its first frame, and a logistic
# regression: what a scalar alone achieves on the same split.
peak = PeakContactChange().fit_transform(data.videos)
t0 = time.perf_counter()
baseline = make_pipeline(StandardScaler(), LogisticRegression()).fit(peak[train], y[train])
base_seconds = time.perf_counter() - t0
base_error = 1 - balanced_accuracy_score(y[test], baseline.predict(peak[test]))
print(f"one number + logistic regression: held-out error {base_error:.2f} (chance {1 - 1 / 5:.2f})")

# %%
# Time against error
# ------------------
fig, ax = plt.subplots(figsize=(5.6, 3.6))
for name, seconds, error in rows:
    ax.plot(seconds, error, "o", color="tab:blue")
    ax.annotate(name, (seconds, error), textcoords="offset points", xytext=(5, 4))
ax.axhline(base_error, ls="--", color="gray", label="one number + logistic regression")
ax.axhline(0.8, ls=":", color="lightgray", label="chance")
ax.set_xlabel("ConvLSTM fit time on 25 presses (s)")
ax.set_ylabel("held-out error (1 - balanced accuracy)")
ax.legend(fontsize=8)
fig.tight_layout()
plt.show()
