"""matplotlib and scikit-image are optional: the core works without them, and what needs one says which extra.

Each check runs in a fresh interpreter with those packages blocked (``sys.modules[name] = None`` makes
``import name`` fail as a missing package does), as on a machine where only the core is installed. tqdm
is no dependency of ours either (skorch, a dependency, installs it): where our code draws a progress
bar without it, it draws none.
"""

import subprocess
import sys
import textwrap

import pytest

OPTIONAL = ("matplotlib", "skimage")


def _run_without_optional(code, tmp_path, blocked=OPTIONAL):
    script = tmp_path / "check.py"
    script.write_text(textwrap.dedent(f"""
        import sys
        for name in {blocked!r}:
            sys.modules[name] = None  # as if not installed
        """) + textwrap.dedent(code))
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0, out.stdout + out.stderr
    return out.stdout


def test_the_core_imports_and_fits_a_named_pipeline_without_the_optional_packages(tmp_path):
    out = _run_without_optional("""
        import importlib
        import numpy as np
        for sub in ("io", "datasets", "preprocessing", "features", "models", "active", "metrics",
                    "model_selection", "experiments", "utils"):
            module = importlib.import_module("sklearn_hardness." + sub)
            for name in module.__all__:
                getattr(module, name)  # every public name resolves
        from sklearn.model_selection import GroupKFold
        from sklearn_hardness.datasets import make_presses
        from sklearn_hardness.model_selection import evaluate_pipelines
        from sklearn_hardness.models import make_named_pipeline

        data = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1],
                            image_size=(32, 40), codec=None, random_state=0)
        pipe = make_named_pipeline("contact_geometry").fit(data.videos, data.target)
        assert pipe.predict(data.videos[:3]).shape == (3,)
        result = evaluate_pipelines(["contact_profile"], data.videos, data.target, groups=data.object_id,
                                    cv=GroupKFold(3), target_names=data.target_names)
        assert np.isfinite(result.summary["balanced_accuracy"]).all()
        print("fitted", [m for m in ("matplotlib", "skimage") if sys.modules.get(m) is not None])
        """, tmp_path)
    assert out.strip().endswith("fitted []")


@pytest.mark.parametrize("call, extra", [
    ("from sklearn_hardness.model_selection import ConfusionMatricesDisplay\n"
     "ConfusionMatricesDisplay({'a': np.eye(2, dtype=int)}).plot()", "plot"),
    ("from sklearn_hardness.preprocessing import ContactFrameSelector, plot_contact_selection\n"
     "plot_contact_selection(ContactFrameSelector().fit([video]))", "plot"),
    ("from sklearn_hardness.experiments import ExperimentResult\n"
     "ExperimentResult([]).save_figures('figures')", "plot"),
    ("from sklearn_hardness.features import ImprintTextureFeatures\n"
     "ImprintTextureFeatures().fit([video])", "texture"),
])
def test_what_needs_an_optional_package_raises_an_import_error_naming_its_extra(call, extra, tmp_path):
    body = "\n".join("    " + line for line in call.splitlines())
    out = _run_without_optional("import numpy as np\n"
                                "video = np.full((6, 16, 16, 3), 100, np.uint8)\n"
                                "video[3:, 4:10, 4:10] = 140\n"
                                f"try:\n{body}\n"
                                "except ImportError as exc:\n    print(exc)\n"
                                "else:\n    print('no error')\n", tmp_path)
    assert f'pip install "sklearn-hardness[{extra}]"' in out, out


def test_the_command_line_simulates_without_tqdm_and_evaluates_without_matplotlib(tmp_path):
    _run_without_optional("""
        from sklearn_hardness._cli import main

        assert main(["simulate", "--preset", "everyday", "--out", "sim", "--n-per-class", "1", "--image-size",
                     "32", "40", "--format", "npy", "--codec", "none"]) == 0
        """, tmp_path, blocked=("tqdm",))
    out = _run_without_optional("""
        import os
        from sklearn_hardness._cli import main

        assert main(["evaluate", "sim", "--pipelines", "--cv", "3", "--out", "out", "--quiet"]) == 0
        print(sorted(os.listdir("out")))
        """, tmp_path)
    assert "['evaluation.json', 'evaluation.txt']" in out


def test_model_selection_imports_neither_torch_nor_scikit_image(tmp_path):
    code = ("import sys, sklearn_hardness.model_selection, sklearn_hardness.models\n"
            "print(sorted(m for m in ('torch', 'skimage', 'matplotlib', 'tqdm') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
