"""Run every gallery example, as sphinx-gallery would, headless, at smaller sizes.

Every line of every example runs; what the test shrinks (frames, epochs, MC passes, repeats) only makes the
figures rougher. The docs build with the gallery (``bash docs/build_docs.sh``) runs them as written.
"""

import os
from pathlib import Path

import matplotlib
import pytest

from ._smaller import smaller

EXAMPLES = sorted((Path(__file__).resolve().parents[1] / "examples").glob("plot_*.py"))

#: What the test shrinks in each example, as README's test does (tests/test_readme_example.py); each text
#: must be in its example. Press counts mostly stay: the protocols need them (initial, queried and test presses).
SMALLER = {
    "plot_active_sampling.py": {
        "image_size=(64, 80)": "image_size=(32, 40)",
        "initial_epochs=20": "initial_epochs=3",
        "epochs_per_query=5": "epochs_per_query=1",
        "n_samples=10": "n_samples=3",
    },
    "plot_dropout_gridsearch.py": {
        "max_epochs=60": "max_epochs=5",
        "n_samples=20": "n_samples=5",
    },
    "plot_model_baselines.py": {
        "n_per_class=20, image_size=(96, 128)": "n_per_class=20, image_size=(48, 64)",
        "DINOv2NNClassifier(max_epochs=50)": "DINOv2NNClassifier(max_epochs=3)",
        "n_runs=3": "n_runs=1",
    },
    "plot_new_object_sampling.py": {
        "n_samples=200": "n_samples=20",
        "[:6]": "[:2]",
        "n_runs=2": "n_runs=1",
    },
    "plot_robot_session.py": {
        "initial_epochs=30": "initial_epochs=3",
        "epochs_per_query=10": "epochs_per_query=1",
        "n_samples=10": "n_samples=3",
    },
    "plot_stopping_rule.py": {
        "image_size=(96, 128)": "image_size=(48, 64)",
        "for test_object in range(len(names))": "for test_object in range(2)",
        "initial_epochs=40": "initial_epochs=3",
        "epochs_per_query=10": "epochs_per_query=1",
        "n_samples=10": "n_samples=3",
    },
    "plot_time_against_error.py": {
        "image_size=(96, 128)": "image_size=(48, 64)",
        "max_epochs=60": "max_epochs=3",
    },
    "plot_unseen_objects.py": {  # half the presses of each of the 42 objects: every fold still has each rank
        'make_presses("everyday", image_size=(96, 128), random_state=0)':
            'make_presses("everyday", image_size=(96, 128), n_per_class=2, random_state=0)',
    },
    "plot_uncertainty_decomposition.py": {
        "image_size=(96, 128)": "image_size=(48, 64)",
        "max_epochs=60": "max_epochs=3",
        "n_samples=50": "n_samples=10",
    },
}


def smaller_source(path):
    """The example's source with :data:`SMALLER`'s replacements made."""
    return smaller(path.read_text(), SMALLER.get(path.name, {}), f"{path.name} (tests/test_examples.py)")


@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_runs(path, monkeypatch, tmp_path):
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    try:
        exec(compile(smaller_source(path), str(path), "exec"), {"__name__": "__main__", "__file__": str(path)})
        assert plt.get_fignums(), f"{path.name} made no figure"
    finally:
        plt.close("all")


def test_examples_exist():
    assert {p.name for p in EXAMPLES} >= {"plot_frame_selection.py", "plot_simulator.py"}
    assert os.path.exists(EXAMPLES[0])
    assert set(SMALLER) <= {p.name for p in EXAMPLES}
    for path in EXAMPLES:  # every replacement still finds its text (the slow tier would say so late)
        smaller_source(path)
