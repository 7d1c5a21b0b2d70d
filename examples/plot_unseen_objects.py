"""
=====================================================
Objects the model has not seen: measure, then choose
=====================================================

A user's own recordings are of objects no model was trained on, and the
useful question is how well a pipeline ranks an object it has never
touched. :func:`~sklearn_hardness.model_selection.evaluate_pipelines` (the
``sklearn-hardness evaluate`` command) answers it with cross-validation
whose folds keep every object's presses together, and runs the simplest
baseline beside every pipeline: one number per press, the peak change of
the frames against the first, with a logistic regression. On real GelSight
Mini recordings of unseen objects that one number was not far behind the
best pipeline and ahead of the paper's nets (the real and simulated figures
side by side are in the simulator page of the docs, "Sim and real side by
side"), so ``evaluate`` recommends a pipeline only where its margin over the
one number is clear of the spread between folds.

This example evaluates the recommended pipeline,
:func:`~sklearn_hardness.models.make_contact_profile_pipeline`, beside the
one number on the built-in ``everyday`` simulator, then shows what a
region of interest does for a sensor whose frame shows more than the gel
(a GelSight Wedge grasp shows its housing and the other finger). The nets
are left out to keep it quick: ``evaluate_pipelines(None, data.videos, ...)`` with no
pipeline list runs them too. Frames are kept small (96x128).
"""

# %%
# Object-disjoint evaluation beside the one number
# -------------------------------------------------
import matplotlib.pyplot as plt
import numpy as np
from sklearn.utils import Bunch

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.model_selection import ConfusionMatricesDisplay, evaluate_pipelines
from sklearn_hardness.models import make_named_pipeline

data = make_presses("everyday", image_size=(96, 128), random_state=0)
data.videos = list(data.videos)  # the simulator renders a video each time it is read: render each once
print(len(data.target), "presses of", len(set(data.object_id)), "objects")
result = evaluate_pipelines(["contact_profile"], data.videos, data.target, groups=data.object_id, cv=5,
                            target_names=data.target_names, hardness=data.hardness, n_jobs=2, random_state=0)
print(result)

# %%
# ``result.cv_results_`` holds one entry per pipeline and fold, as
# scikit-learn's ``cross_validate`` gives them for one estimator: a table for
# pandas, from which the summary above is derived.
import pandas as pd

folds = pd.DataFrame(result.cv_results_)
print(folds.pivot(index="split", columns="pipeline", values="test_balanced_accuracy").round(2))

# %%
# The table gives each pipeline's balanced accuracy (chance: 1/3) with its
# 95% interval over the folds, and its margin over the one number paired by
# fold. ``recommended`` is None when no margin's interval lies above 0: then
# the one number does as well within what five folds of these objects can
# tell, and more objects, not more repetitions, would narrow the intervals.
# Below the table, ``per object`` scores the test objects instead of the
# presses (an object's class: the mean of its presses' probabilities), and
# each pipeline's recall per class says which ranks it misses; the confusion
# matrices show where those presses went.
fig = ConfusionMatricesDisplay.from_result(result).figure_
plt.show()

# %%
# A frame that shows more than the gel
# ------------------------------------
# A grasping sensor's frame holds the gel and, around it, parts that change
# for reasons of their own (the housing catching light as the gripper
# moves). Here each press is put in the middle of a larger frame whose
# border brightens at a random time, as in a grasp. Read on the whole frame,
# that change swamps the press; ``roi=(top, bottom, left, right)``, in
# fractions of the frame, reads the gel only, in the baseline and in every
# pipeline given by name (``sklearn-hardness evaluate ... --roi``; the
# factories take the same ``roi``).
rng = np.random.default_rng(0)


def framed(video):
    """``video`` (T, 96, 128, 3) on the gel of a 160x192 frame whose border brightens from a random frame."""
    n = len(video)
    start, rise = int(rng.integers(0, n)), int(rng.integers(1, 20))
    border = 90 + 60 * np.clip((np.arange(n) - start + 1) / rise, 0, 1)
    frame = np.empty((n, 160, 192, 3), np.uint8)
    frame[:] = border.astype(np.uint8)[:, None, None, None]
    frame[:, 32:128, 32:160] = video
    return frame


wide = Bunch(videos=[framed(v) for v in data.videos], target=data.target, target_names=data.target_names,
             object_id=data.object_id, hardness=data.hardness)
gel = (32 / 160, 128 / 160, 32 / 192, 160 / 192)


def evaluate(roi):
    """The contact profile and the one number, both reading ``roi`` of the frames."""
    return evaluate_pipelines({"contact_profile": make_named_pipeline("contact_profile", roi=roi)}, wide.videos,
                              wide.target, groups=wide.object_id, cv=5,
                              baseline=("peak_change", make_named_pipeline("peak_change", roi=roi)),
                              target_names=wide.target_names, n_jobs=2, random_state=0)


whole, on_gel = evaluate(None), evaluate(gel)
for name, res in [("whole frame", whole), ("roi on the gel", on_gel)]:
    print(name, dict(zip(res.summary["pipeline"], np.round(res.summary["balanced_accuracy"], 2).tolist())))

# %%
# On the gel both pipelines score as on the plain presses above; on the
# whole frame they read the border's change. The contact curves of four
# videos show why: on the whole frame the border's step is the largest
# change of each video (and the selector warns that it finds no contact in
# one of them), on the gel only the press remains.
# :class:`~sklearn_hardness.preprocessing.ContactFrameSelector` takes the
# same ``roi`` (``sklearn-hardness select ... --roi``), so a region can be
# checked on a few videos before any training.
from sklearn_hardness.preprocessing import ContactFrameSelector, plot_contact_selection

fig, axes = plt.subplots(1, 2, figsize=(10, 3.5), layout="constrained")
long_videos = [v for v in wide.videos if len(v) > 60][:4]
for ax, roi, title in [(axes[0], None, "whole frame"), (axes[1], gel, "roi on the gel")]:
    selection = ContactFrameSelector(roi=roi, on_no_contact="fallback").select(long_videos)
    plot_contact_selection(selection, ax=ax)
    ax.set_title(title)
plt.show()
