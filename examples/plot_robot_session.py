"""
A robot session: press a new object, then the reference objects the learner asks for
=====================================================================================

The task of the paper, as a robot does it: press a *new* test object a few
times, then, query after query, press the *reference object* the strategy
asks for, retrain, and stop once the decision on the test object is settled
(:class:`~sklearn_hardness.active.ActiveLearner`'s ``stop_threshold``).

With many reference objects per hardness class, the learner asks for a
*class* (Eq. 1-2 score classes) and a :class:`~sklearn_hardness.active.PressOracle`
over the catalogue of reference objects answers with the *object* to press:
the one of that class pressed least so far, ties broken at random.

The source of frames is a :class:`~sklearn_hardness.datasets.SimulatedSensor`
here, so the session runs without hardware. With a GelSight Mini, use the
camera instead (``source = 0``, the device index, or a video file) and let the
robot press the object before each recording: only the ``press`` function
below changes.
"""

# %%
# The objects on the table
# ------------------------
# Nine simulated everyday objects, three per hardness rank; one is the new
# test object, the other eight are the reference objects with their known rank.
import warnings

import matplotlib.pyplot as plt
import numpy as np

from sklearn_hardness.active import ActiveLearner, PressOracle
from sklearn_hardness.datasets import SimulatedSensor, make_presses
from sklearn_hardness.io import record_video
from sklearn_hardness.models import ConvLSTMClassifier
from sklearn_hardness.preprocessing import ContactFrameSelector, ContactNotFoundWarning

data = make_presses("everyday", n_per_class=3, n_objects=9, class_ratio=[1, 1, 1], image_size=(48, 64),
                    random_state=0)
objects = np.unique(data.object_id)
rank = {o: int(data.target[data.object_id == o][0]) for o in objects}
test_object = objects[0]
reference = [o for o in objects if o != test_object]
print(f"test object: {test_object} (rank {data.target_names[rank[test_object]]}, unknown to the robot)")

sensor = SimulatedSensor(data, random_state=0)  # a real session: source = 0 (camera) or "press.avi"
# soft objects barely change the image: a press without detected contact keeps the fallback frames
select = ContactFrameSelector(n_between=2, frame_size=(12, 16), color="gray", on_no_contact="fallback")
warnings.filterwarnings("ignore", category=ContactNotFoundWarning)


def press(obj):
    """The robot presses ``obj`` once; the sensor records the press (selected frames)."""
    sensor.press(obj)  # with a camera: move the arm and press obj here
    video = record_video(sensor, n_frames=sensor.n_frames)  # with a camera: record_video(0, duration=5)
    return select.fit_transform([video])


# %%
# Press the test object, then two presses of one object of every rank
# -------------------------------------------------------------------
# ``catalogue`` holds planned presses of every reference object (many per
# object: a robot can press an object again and again); ``press_object``
# names the least-pressed object of the asked class.
X_test = np.concatenate([press(test_object) for _ in range(3)])
catalogue = PressOracle(np.repeat(reference, 50), np.repeat([rank[o] for o in reference], 50),
                        groups=np.repeat(reference, 50), random_state=0)
s = 2  # presses per query
X0, y0, log = [], [], []
for c in range(len(data.target_names)):
    obj, _, y_new = catalogue.press_object(c, s)
    X0 += [press(obj) for _ in y_new]
    y0 += y_new.tolist()
    log.append(("initial", obj))

learner = ActiveLearner(
    ConvLSTMClassifier(dropout=0.2, lr=3e-3, random_state=0), "thompson", initial_epochs=30,
    epochs_per_query=10, n_samples=10, stop_threshold=0.7, stop_patience=2, max_presses=12,
    classes=np.arange(len(data.target_names)), random_state=0,
)
learner.fit(np.concatenate(X0), np.array(y0))

# %%
# Ask, press, update, until the stopping rule ends the session
# ------------------------------------------------------------
while True:
    idx, _ = learner.query(X_test)
    if learner.stop_reason_ is not None:
        break
    obj, _, y_new = catalogue.press_object(learner.classes_[idx[0]], s)
    learner.teach(np.concatenate([press(obj) for _ in y_new]), y_new)
    log.append((f"query {len(log) - 2}", obj))

queries = [h for h in learner.history_ if h["event"] == "query"]
decision = queries[-1]["decision"]
for step, obj in log:
    print(f"{step:>9}: pressed {obj} ({data.target_names[rank[obj]]}) {s} times")
print(f"stopped ({learner.stop_reason_}) after {learner.n_presses_} extra presses: "
      f"{test_object} is {data.target_names[decision]} (truly {data.target_names[rank[test_object]]}), "
      f"confidence {queries[-1]['confidence']:.2f}")

# %%
# One session is an anecdote; ``run_active_sampling("everyday")`` replays many
# such sessions object-disjoint (one test object per run, none of its presses
# trained on) and reports, per strategy, the presses to reach random's final
# accuracy and the presses and accuracy at the stopping rule, with paired
# intervals.
#
# The decision's confidence, query by query
# -----------------------------------------
# The mean MC-dropout probability of the decided rank on the test presses at
# each query, with the reference object pressed after it; the session ends at
# the last point (dashed: the threshold).
fig, ax = plt.subplots(figsize=(6.4, 3.6))
conf = [q["confidence"] for q in queries]
ax.plot(np.arange(len(conf)), conf, "o-")
for k, (_, obj) in enumerate(log[3:]):
    ax.annotate(obj.split("-", 2)[-1], (k, conf[k]), textcoords="offset points", xytext=(4, 6), fontsize=8)
ax.axhline(0.7, ls="--", color="gray")
ax.set_xticks(np.arange(len(conf)))
ax.set_xlabel("query")
ax.set_ylabel("confidence of the decision")
ax.set_title(f"test object {test_object}")
fig.tight_layout()
plt.show()
