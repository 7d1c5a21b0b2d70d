"""
========================================
Model baselines: five presses per object
========================================

The paper (Sec. III-D, Fig. 3) trains each classifier on five presses per
reference object and tests it on held-out presses. Here we run the same
protocol on simulated ``silicone5`` presses with
:func:`~sklearn_hardness.experiments.run_model_baselines`, in its ``quick``
setting: 20 presses per object instead of 91, smaller images, fewer epochs
and runs than the paper, so that it is quick to run.

The paper's numbers on its robot data were ConvLSTM 42%, DINOv2NN 38% and
OFNN 27% (chance: 20%). DINOv2NN needs the pretrained DINOv2-S/14 weights,
which this example cannot download; it runs the same code path on a tiny
*randomly initialised* backbone, so its accuracy here is a smoke test of the
pipeline, not a result.
"""

# %%
# A tiny random DINOv2 backbone (stand-in for ``facebook/dinov2-small``)
# ------------------------------------------------------------------------
import matplotlib.pyplot as plt
from sklearn.pipeline import Pipeline
from transformers import Dinov2Config, Dinov2Model

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.experiments import (
    run_model_baselines,
)
from sklearn_hardness.features import DINOv2Features
from sklearn_hardness.models import DINOv2NNClassifier

tiny = Dinov2Model(
    Dinov2Config(
        hidden_size=32, num_hidden_layers=2, num_attention_heads=2, intermediate_size=64, image_size=56, patch_size=14
    )
)
dinov2_random = Pipeline(
    [("features", DINOv2Features(model=tiny, image_size=56)), ("clf", DINOv2NNClassifier(max_epochs=50))]
)

# %%
# Run the baselines
# -----------------
# With real weights, pass ``"dinov2nn"`` and ``dinov2_model="path/to/dinov2-small"``.
# Each run draws 5 training and 5 test presses per object from 20.
presses = make_presses("silicone5", n_per_class=20, image_size=(96, 128), random_state=0)
result = run_model_baselines(
    presses,
    models=("ofnn", "convlstm", ("dinov2nn (random weights)", dinov2_random)),
    n_runs=3,
    quick=True,
    n_jobs=2,
    verbose=0,
)
print(result.format_table(result.baseline_table(), mae_unit="mm/N"))

# %%
# Train and test accuracy per model
# ---------------------------------
result.plot_model_baselines()
plt.show()
