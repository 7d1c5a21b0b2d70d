"""
========================================
Choosing the dropout rate by grid search
========================================

Dropout does two jobs here: it regularises the classifier and, kept on at
prediction time, it gives the Monte-Carlo samples whose spread drives active
sampling. The paper (Sec. III-E) found rates above 0.2 degrade accuracy.

``dropout`` is a plain parameter of every classifier, so a standard
:class:`~sklearn.model_selection.GridSearchCV` over ``clf__dropout`` works.
Optical-flow features come from a frozen procedure, so we compute them once
and search over the classifier head only, scoring accuracy and the paper's
hardness MAE side by side.
"""

# %%
# Simulated presses and optical-flow features, computed once
# ------------------------------------------------------------
import matplotlib.pyplot as plt
import numpy as np
from sklearn.model_selection import GridSearchCV, StratifiedKFold
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.features import OpticalFlowFeatures
from sklearn_hardness.metrics import make_hardness_mae_scorer
from sklearn_hardness.models import OFNNClassifier
from sklearn_hardness.preprocessing import ContactFrameSelector

data = make_presses("silicone5", n_per_class=12, image_size=(120, 160), random_state=0)
selector = ContactFrameSelector(n_between=2, subtract_first=False, color="gray")
frames = selector.fit_transform(data.videos)
features = OpticalFlowFeatures(n_features=80).fit_transform(frames)
print("features:", features.shape)

# %%
# Grid search over the dropout rate
# ---------------------------------
pipe = Pipeline(
    [
        ("scale", StandardScaler()),
        ("clf", OFNNClassifier(max_epochs=60, lr=3e-3, random_state=0)),
    ]
)
search = GridSearchCV(
    pipe,
    {"clf__dropout": [0.0, 0.05, 0.1, 0.2, 0.3, 0.5]},
    scoring={"accuracy": "accuracy", "mae": make_hardness_mae_scorer(data.hardness)},
    refit="accuracy",
    cv=StratifiedKFold(4, shuffle=True, random_state=0),
)
search.fit(features, data.target)
print("best dropout:", search.best_params_["clf__dropout"])

# %%
# Accuracy and hardness MAE against the dropout rate
# ----------------------------------------------------
res = search.cv_results_
rates = np.array(res["param_clf__dropout"], dtype=float)
fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(9, 3.5))
ax0.errorbar(rates, res["mean_test_accuracy"], res["std_test_accuracy"], marker="o", capsize=3)
ax0.axhline(1 / len(data.target_names), color="0.6", ls=":", label="chance")
ax0.set(xlabel="dropout", ylabel="accuracy", title="4-fold CV accuracy")
ax0.legend()
ax1.errorbar(rates, -res["mean_test_mae"], res["std_test_mae"], marker="o", capsize=3, color="C1")
ax1.set(xlabel="dropout", ylabel=f"MAE ({data.hardness_unit})", title="hardness MAE")
fig.tight_layout()

# %%
# What the rate means for active sampling
# ---------------------------------------
# Every classifier of the library reports Monte-Carlo-dropout samples. Their
# spread over passes is what the strategies score, and it is zero without
# dropout: a rate of 0 may classify well but leaves nothing to choose by. We
# refit at the best rate and at the paper's 0.2 and compare the spread.
from sklearn.base import clone

for rate in sorted({search.best_params_["clf__dropout"], 0.2}):
    net = clone(pipe).set_params(clf__dropout=rate).fit(features, data.target)
    X_scaled = net[0].transform(features[:3])
    samples = net[-1].predict_proba_samples(X_scaled, n_samples=20, random_state=0)
    spread = samples.std(axis=0).mean()
    print(f"dropout {rate}: samples {samples.shape}, mean spread over passes {spread:.1e}")
plt.show()
