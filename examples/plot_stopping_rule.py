"""
Pressing until sure: a simulated robot session with a stopping rule
===================================================================

The paper always makes ``N`` queries and reports the accuracy after them. A
robot wants to stop pressing as soon as its decision on the test object is
settled. :class:`~sklearn_hardness.active.ActiveLearner` has an optional
stopping rule: the *decision* is the class with the highest mean MC-dropout
probability on the test presses, and the learner stops when that mean
probability is at least ``stop_threshold`` and the decision was the same in
the last ``stop_patience`` queries, or when ``max_presses`` reference presses
were spent.

Here a simulated robot classifies each of the five silicone objects in turn,
pressing reference objects chosen by the ``margin`` strategy until it is sure.
"""

# %%
# Simulated presses and their contact frames
# ------------------------------------------
import matplotlib.pyplot as plt
import numpy as np

from sklearn_hardness.active import ActiveLearner, PressOracle
from sklearn_hardness.datasets import make_presses
from sklearn_hardness.models import ConvLSTMClassifier
from sklearn_hardness.preprocessing import ContactFrameSelector

data = make_presses("silicone5", n_per_class=30, image_size=(96, 128), random_state=0)
frames = ContactFrameSelector(n_between=2, frame_size=(12, 16), color="gray").fit_transform(data.videos)
y = data.target
names = data.target_names

# %%
# One session per test object
# ---------------------------
# For each test object, five of its presses are the *test presses*; the robot
# starts from three presses of every reference object and then presses five
# more of the object the strategy picks, until the rule stops it (at most 20
# extra presses: four queries of five presses).
sessions = []
for test_object in range(len(names)):
    rng = np.random.default_rng(test_object)
    test = rng.choice(np.flatnonzero(y == test_object), 5, replace=False)
    pool = np.setdiff1d(np.arange(len(y)), test)
    oracle = PressOracle(frames[pool], y[pool], random_state=test_object)
    clf = ConvLSTMClassifier(dropout=0.2, random_state=test_object)
    learner = ActiveLearner(
        clf, "margin", initial_epochs=40, epochs_per_query=10, n_samples=10,
        stop_threshold=0.7, stop_patience=2, max_presses=20, random_state=test_object,
    )
    learner.fit(*oracle.initial(3))
    while True:
        idx, _ = learner.query(frames[test])
        if learner.stop_reason_ is not None:
            break
        learner.teach(*oracle.press(learner.classes_[idx[0]], 5))
    queries = [h for h in learner.history_ if h["event"] == "query"]
    decision = queries[-1]["decision"]
    sessions.append({"test": test_object, "queries": queries, "presses": learner.n_presses_,
                     "reason": learner.stop_reason_, "correct": decision == test_object})
    print(f"test object {names[test_object]:>6}: stopped ({learner.stop_reason_}) after "
          f"{learner.n_presses_:>2} extra presses, decided {names[decision]} "
          f"({'right' if decision == test_object else 'wrong'}), confidence {queries[-1]['confidence']:.2f}")

print(f"{sum(s['correct'] for s in sessions)} of {len(sessions)} right with "
      f"{np.mean([s['presses'] for s in sessions]):.1f} extra presses on average (fixed: 20)")

# %%
# The confidence of the decision, query by query
# ----------------------------------------------
# Each line is one session: the mean MC probability of the decided class on
# the test presses at each query; a filled marker where the decision was
# right. The session ends at its last point (the dashed line is the
# threshold).
fig, ax = plt.subplots(figsize=(6.4, 3.8))
for s in sessions:
    conf = [q["confidence"] for q in s["queries"]]
    presses = 5 * np.arange(len(conf))
    (line,) = ax.plot(presses, conf, "-", label=f"test object {names[s['test']]}")
    right = np.array([q["decision"] == s["test"] for q in s["queries"]])
    ax.plot(presses[right], np.array(conf)[right], "o", color=line.get_color())
    ax.plot(presses[~right], np.array(conf)[~right], "o", mfc="white", color=line.get_color())
ax.axhline(0.7, ls="--", color="gray")
ax.set_xlabel("extra reference presses")
ax.set_ylabel("confidence of the decision")
ax.legend(fontsize=8)
fig.tight_layout()
plt.show()

# %%
# Over many paired runs
# ---------------------
# One session per object is an anecdote. The experiments replay the same kind
# of rule on every finished run (on the votes of the test presses: the decision
# is settled when 80% of them agree for 2 iterations) and report, per strategy,
# the presses used and the accuracy at the stop with 95% paired intervals
# (``presses_at_stop`` and ``accuracy_at_stop`` in
# :meth:`~sklearn_hardness.experiments.ExperimentResult.paired_table`).
