"""
Which reference object to press next: comparing active-sampling strategies
==========================================================================

A robot has pressed a *test object* a few times and must tell which of five
silicone *reference objects* it matches in hardness. After five presses of
every reference object, it may press more: which object should it press
next? The paper's answer is the one on which the classifier's Monte-Carlo
dropout predictions for the test presses vary the most (Algorithm 1).

Here we run that experiment on the built-in simulator with a small ConvLSTM
and settings scaled down to run in about a minute: one seed per test object,
fewer epochs, tiny frames. ``sklearn-hardness reproduce`` runs the paper's
full setup; this example shows the functions behind it.
"""

# %%
# Simulated presses
# -----------------
# ``make_presses`` simulates GelSight press videos of the paper's five
# silicone objects (compliance 1.13 ... 0.44 mm/N). 24 presses per object
# are enough here: each run needs 5 initial presses per object, 5 test
# presses and up to 5 x 2 more presses of the queried objects.
import matplotlib.pyplot as plt

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.experiments import (
    run_active_sampling,
)

data = make_presses("silicone5", n_per_class=24, image_size=(64, 80), random_state=0)
print(data.target_names, data.hardness, data.hardness_unit)

# %%
# The experiment
# --------------
# A run is (strategy, test object, seed). Runs with the same test object and
# seed share the test presses, the initial presses and the initial training,
# so the strategies are compared on paired runs. With one seed per test
# object the numbers below are anecdotes; the paper averages 50 runs. ``n_jobs`` runs them in
# parallel through joblib; ``results_path`` would make the experiment
# resumable.
result = run_active_sampling(
    data,
    model="convlstm",
    strategies=("variance", "random"),
    n_runs=1,
    n_iterations=2,
    n_per_query=5,
    initial_epochs=20,
    epochs_per_query=5,
    lr=3e-3,
    n_samples=10,
    frame_size=(9, 12),
    # With 20 epochs most runs end above the paper's convergence threshold
    # (training loss 1): keep them all here instead of skipping them.
    convergence_threshold=None,
    n_jobs=2,
    verbose=0,
)
print(result.format_table(result.comparison_table(), mae_unit=data.hardness_unit))

# %%
# Every run is a plain dict: per-iteration accuracy (dropout off), hardness
# MAE, the per-class uncertainty on the test presses and the queried object.
run = result.records[0]
print(run["key"], run["accuracy"], run["queried"])

# %%
# Figures like the paper's
# ------------------------
# Accuracy and MAE per iteration (mean and standard deviation over runs),
# and the mean entropy and variance of the MC-dropout predictions.
fig, axes = plt.subplots(2, 2, figsize=(9, 6.5), layout="constrained")
result.plot_active_sampling("accuracy", ax=axes[0, 0])
result.plot_active_sampling("mae", ax=axes[0, 1])
result.plot_uncertainty("entropy", ax=axes[1, 0])
result.plot_uncertainty("variance", ax=axes[1, 1])
fig.suptitle("Active sampling on simulated silicone5 presses (1 seed per test object)")
