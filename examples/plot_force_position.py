"""
=================================================
When the robot records force and position
=================================================

A press video alone confuses a soft object with a hard one pressed less:
the gel shows how deep it is pushed, not how hard. A robot (or a gripper)
that records its force and its position at each frame measures what
hardness is: how far the sensor travels into the object per unit force.
:class:`~sklearn_hardness.features.LoadingCompliance` fits it over each
press's loading phase, and
:func:`~sklearn_hardness.models.make_loading_compliance_pipeline` classifies
it with a balanced logistic regression that has ``predict_proba_samples``
(so active sampling works with it).

The figure it fits by default is the *Hertz compliance*: the slope of the
position against ``force^(2/3)``. A dome pressed into an elastic object
sinks as ``delta = c F^(2/3)`` (Hertz contact), so ``c`` is the same
whatever force the press reaches, where the plain slope against force is
not: a model trained on presses of a few newtons then reads grasps of tens
of newtons. This example shows both on the built-in simulator (its
``position`` is the sensor's, as joint encoders measure it; videos are not
rendered here), beside the one number of the video, and what happens with
an impedance controller's *commanded* position instead.
"""

# %%
# Force and position of simulated presses
# ---------------------------------------
import warnings

import matplotlib.pyplot as plt
import numpy as np
from sklearn.metrics import balanced_accuracy_score
from sklearn.model_selection import StratifiedGroupKFold, cross_val_score

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.features import LoadingCompliance
from sklearn_hardness.models import make_loading_compliance_pipeline

warnings.simplefilter("ignore", UserWarning)  # presses cut short: their figures are NaN, then imputed

data = make_presses("everyday", random_state=0)  # the videos are lazy: never rendered below
X = [np.column_stack([force, position]) for force, position in zip(data.force, data.position)]
firm = make_presses("everyday", random_state=1, force_range=(15.0, 25.0))  # pushed four times harder
X_firm = [np.column_stack([force, position]) for force, position in zip(firm.force, firm.position)]

figures = LoadingCompliance().fit(X)
fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharex=True)
for ax, column, unit in zip(axes, [0, 1], ["mm/N$^{2/3}$", "mm/N"]):
    for presses, marker in [(X, "o"), (X_firm, "^")]:
        target = data.target if presses is X else firm.target
        F = figures.transform(presses)
        for k, name in enumerate(data.target_names):
            ax.scatter(F[target == k, 3], F[target == k, column], s=10, marker=marker, alpha=0.6,
                       color=f"C{k}", label=name if presses is X else None)
    ax.set(xscale="log", yscale="log", xlabel="peak force (N)",
           ylabel=f"{figures.features_[column].replace('_', ' ')} ({unit})")
axes[0].legend(title="rank (o: 1-6 N, ^: 15-25 N)", fontsize=8)
axes[0].set_title("against force$^{2/3}$: flat in force", fontsize=10)
axes[1].set_title("against force: stiffer when pushed harder", fontsize=10)
fig.tight_layout()
plt.show()

# %%
# New objects, and presses pushed harder
# --------------------------------------
# Object-disjoint cross-validation (no test object is seen in training), as
# ``sklearn-hardness evaluate everyday --pipelines loading_compliance`` runs
# it beside the video pipelines. Peak force alone is the simplest scalar
# beside it. Then each pipeline, trained on the 1-6 N presses, predicts the
# presses pushed to 15-25 N.
cv = StratifiedGroupKFold(n_splits=5, shuffle=True, random_state=0)
for name in ["hertz_compliance", "linear_compliance", "peak_force"]:
    pipe = make_loading_compliance_pipeline(features=[name])
    new_objects = cross_val_score(pipe, X, data.target, groups=data.object_id, cv=cv,
                                  scoring="balanced_accuracy").mean()
    harder = balanced_accuracy_score(firm.target, pipe.fit(X, data.target).predict(X_firm))
    print(f"{name:18s} new objects {new_objects:.2f}   pushed 4x harder {harder:.2f}")

# %%
# A commanded position
# --------------------
# An impedance controller's setpoint runs ahead of the sensor by the
# controller's give, its compliance times the force. Left in, that linear
# term swamps the Hertz fit at high forces; ``drive_compliance`` takes it off
# (here the simulator's, 0.3 mm/N: a Cartesian stiffness of about 3300 N/m).
data = make_presses("everyday", random_state=0, return_mechanics=True)
firm = make_presses("everyday", random_state=1, force_range=(15.0, 25.0), return_mechanics=True)
commanded = [np.column_stack([f, m["position"]]) for f, m in zip(data.force, data.mechanics)]
commanded_firm = [np.column_stack([f, m["position"]]) for f, m in zip(firm.force, firm.mechanics)]
for give in [0.0, data.params["drive_compliance"]]:
    pipe = make_loading_compliance_pipeline(drive_compliance=give)
    pipe.fit(commanded, data.target)
    score = balanced_accuracy_score(firm.target, pipe.predict(commanded_firm))
    print(f"drive_compliance={give:.1f} mm/N: pushed 4x harder {score:.2f}")
