"""
What drives a query: the MC and the between-press parts of the variance
========================================================================

The paper picks the next reference object by the variance of the
Monte-Carlo-dropout probabilities of each class, pooled over the dropout
passes *and* the test presses (Eq. 2). By the law of total variance that
pooled variance is the sum of two parts
(:func:`~sklearn_hardness.active.variance_decomposition`):

* the **MC part**: how much the passes of one press disagree, the model's
  own (epistemic) uncertainty under dropout;
* the **between-press part**: how differently the test presses are
  classified, which stays when dropout is off.

Only the first is what "uncertainty sampling" means. Here we train the
ConvLSTM with each of its dropout placements on five simulated presses per
object and look at which part drives the query.
"""

# %%
# Presses and contact frames
# --------------------------
# Five training presses of each of the five silicone objects and five
# held-out presses of one *test object*. The contact frames are selected once
# and shared by the three classifiers below.
import matplotlib.pyplot as plt
import numpy as np

from sklearn_hardness.active import class_uncertainty, variance_decomposition
from sklearn_hardness.datasets import make_presses
from sklearn_hardness.models import ConvLSTMClassifier
from sklearn_hardness.preprocessing import ContactFrameSelector

data = make_presses("silicone5", n_per_class=10, image_size=(96, 128), random_state=0)
frames = ContactFrameSelector(n_between=2, frame_size=(18, 24), color="gray").fit_transform(data.videos)
y = data.target
rng = np.random.default_rng(0)
train = np.concatenate([rng.choice(np.flatnonzero(y == c), 5, replace=False) for c in np.unique(y)])
test_object = 2
test = np.setdiff1d(np.flatnonzero(y == test_object), train)
print(f"{len(train)} training presses, {len(test)} presses of test object {data.target_names[test_object]}")

# %%
# Three dropout placements
# ------------------------
# ``"layers"`` is the paper's (spatial dropout after every ConvLSTM layer,
# before a global-average pool), ``"channels"`` drops whole feature maps in
# the recurrent layers, ``"head"`` (the default) drops the pooled features
# before the classifier. Same data, seed and dropout rate 0.2.
decompositions = {}
for placement in ("layers", "channels", "head"):
    clf = ConvLSTMClassifier(dropout=0.2, dropout_placement=placement, max_epochs=60, random_state=0)
    clf.fit(frames[train], y[train])
    samples = clf.predict_proba_samples(frames[test], n_samples=50, random_state=0)
    d = variance_decomposition(samples)
    # the decomposition is exact: its parts add up to the paper's Eq. 2
    np.testing.assert_allclose(d["mc"] + d["between"], class_uncertainty(samples, "variance"), atol=1e-9)
    decompositions[placement] = d
    share = d["mc"].sum() / max(d["total"].sum(), 1e-12)
    print(
        f"{placement:>8}: query -> {data.target_names[int(np.argmax(d['total']))]:<12} "
        f"MC share of the pooled variance {share:.2f}"
    )

# %%
# Which part drives the query
# ---------------------------
# Stacked bars per class: the MC part (dark) under the between-press part
# (light). The queried class is the highest bar. Where the light part
# dominates, the query follows how differently the test presses look, not
# what the model does not know.
fig, axes = plt.subplots(1, 3, figsize=(11, 3.2), sharey=True)
x = np.arange(len(data.target_names))
for ax, (placement, d) in zip(axes, decompositions.items()):
    ax.bar(x, d["mc"], color="tab:blue", label="MC part")
    ax.bar(x, d["between"], bottom=d["mc"], color="tab:blue", alpha=0.35, label="between presses")
    ax.set_xticks(x, data.target_names, rotation=45, ha="right")
    ax.set_title(f'dropout_placement="{placement}"')
axes[0].set_ylabel("variance of class probability (Eq. 2)")
axes[0].legend()
fig.tight_layout()
plt.show()

# %%
# On many trained nets rather than one
# ------------------------------------
# One net and one test object are an anecdote.
# ``python studies/scripts/mc_share.py --seeds 3`` measures the MC share over
# seeds for each placement: at dropout 0.2 none reaches half of Eq. 2, and the
# paper's placement gives the smallest. Every active-sampling run records both parts
# per iteration (``variance_mc`` and ``variance_between`` in its history),
# and the strategy ``"mc_variance"`` ranks classes by the MC part alone.
