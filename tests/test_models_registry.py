"""One table of named pipelines: a name is one model in evaluate, reproduce, the command line and for users."""

import ast
import pathlib
import re
import subprocess
import sys

import pytest
from sklearn.base import BaseEstimator

from sklearn_hardness import models
from sklearn_hardness._cli._evaluate import _estimators
from sklearn_hardness.experiments import EXPERIMENT_MODELS, get_config
from sklearn_hardness.experiments._config import check_config
from sklearn_hardness.experiments._models import make_estimator, model_pipeline
from sklearn_hardness.models import (
    make_convlstm_pipeline,
    make_named_pipeline,
    make_ofnn_pipeline,
    pipeline_info,
    pipeline_names,
)
from sklearn_hardness.models._registry import PipelineInfo

PACKAGE = pathlib.Path(__file__).resolve().parents[1] / "sklearn_hardness"
NAMES = ("peak_change", "contact_geometry", "contact_profile", "contact_profile_3", "imprint_texture",
         "contact_profile_nn", "convlstm", "convlstm_intensity", "ofnn", "ofnn_quantiles", "dinov2nn", "imprint_cnn",
         "loading_compliance")


def _params(estimator):
    """``get_params(deep=True)`` as text, nested estimators and callbacks by type, not by identity."""
    out = {"": type(estimator).__name__}
    for key, value in estimator.get_params(deep=True).items():
        if isinstance(value, BaseEstimator):
            value = type(value).__name__  # its parameters are items of their own
        out[key] = re.sub(r" (object )?at 0x[0-9a-f]+", "", repr(value))
    return out


def test_names_list_build_and_describe():
    assert pipeline_names() == NAMES
    assert pipeline_names(input="force_position") == ("loading_compliance",)
    assert "loading_compliance" not in pipeline_names(input="video")
    defaults = [n for n in NAMES if pipeline_info(n).default]
    assert defaults == ["contact_geometry", "contact_profile"] and set(EXPERIMENT_MODELS) <= set(NAMES)
    for name in NAMES:  # each names its factory, a public function of models
        assert callable(getattr(models, pipeline_info(name).builder)), name
    for name in NAMES:
        info = pipeline_info(name)
        assert isinstance(info, PipelineInfo) and info.name == name and info.summary
        pipe = make_named_pipeline(name, random_state=0)
        assert hasattr(pipe, "predict_proba_samples") == info.samples, name
        assert make_named_pipeline(name) is not make_named_pipeline(name)  # fresh each time
        seeded = [k for k, v in pipe.get_params().items() if k.endswith("random_state") and v == 0]
        assert bool(seeded) == info.random, name
    with pytest.raises(AttributeError):
        pipeline_info("convlstm").samples = False  # frozen


def test_unknown_names_and_fixed_arguments_fail_clearly():
    for call in (lambda: make_named_pipeline("lstm"), lambda: pipeline_info("lstm")):
        with pytest.raises(ValueError, match="unknown pipeline name 'lstm'.*convlstm_intensity"):
            call()
    with pytest.raises(ValueError, match="input must be"):
        pipeline_names(input="frames")
    with pytest.raises(TypeError, match="fixed by the name 'ofnn'.*ofnn_quantiles"):
        make_named_pipeline("ofnn", flow_output="magnitude_quantiles")
    # other arguments reach the builder
    assert make_named_pipeline("convlstm", roi=(0.1, 0.9, 0.1, 0.9)).named_steps["frames"].roi == (0.1, 0.9, 0.1, 0.9)


def _pipeline_by_name(name, seed, roi=None):
    """What ``sklearn-hardness evaluate --pipelines NAME --seed SEED [--roi ...]`` fits."""
    return _estimators([name], None, roi, seed)[name]


def test_renamed_variants_build_what_evaluate_built_before():
    """``convlstm_intensity`` and ``ofnn_quantiles`` are evaluate's former ``convlstm`` and ``ofnn``."""
    roi = (0.1, 0.9, 0.05, 0.95)
    assert _params(_pipeline_by_name("convlstm_intensity", 3, roi)) == _params(
        make_convlstm_pipeline(intensity_channels=True, roi=roi, random_state=3))
    assert _params(_pipeline_by_name("ofnn_quantiles", 3, roi)) == _params(make_ofnn_pipeline(roi=roi, random_state=3))
    # the paper's variants keep the plain names
    assert "intensity" not in make_named_pipeline("convlstm").named_steps
    assert make_named_pipeline("ofnn").named_steps["features"].output == "tracks"


@pytest.mark.parametrize("name", EXPERIMENT_MODELS)
@pytest.mark.parametrize("preset", ["silicone5", "shore9"])
def test_evaluate_and_reproduce_build_the_same_estimator(name, preset):
    """Evaluate's pipeline, given the run's documented settings, is reproduce's, to the last parameter."""
    cfg = check_config(get_config(preset, model=name))
    seed = 7
    theirs = model_pipeline(name, cfg, random_state=seed)
    ours = _pipeline_by_name(name, seed)  # evaluate's
    settings = {"clf__class_weight": cfg["class_weight"], "clf__random_state": seed}  # reproduce's config keys
    if "frames" in ours.named_steps:
        settings.update(frames__n_between=cfg["n_between"], frames__frame_size=cfg["frame_size"])
    if "features" in ours.named_steps and "model" in ours.named_steps["features"].get_params():
        settings["features__model"] = cfg["dinov2_model"]
    ours.set_params(**settings)
    assert _params(ours) == _params(theirs)
    # and each run's classifier is that pipeline's last step with the run's training settings
    net = make_estimator(name, cfg, seed, n_classes=5)
    assert type(net) is type(theirs.named_steps["clf"])


def test_no_other_module_maps_names_to_builders():
    """Only the registry names the builders; the former tables and functions are gone."""
    builders = ("make_convlstm_pipeline", "make_ofnn_pipeline", "make_dinov2nn_pipeline",
                "make_contact_profile_pipeline", "make_loading_compliance_pipeline", "make_peak_change_baseline")
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel in ("models/_registry.py", "models/__init__.py", "models/_pipelines.py", "models/_peak_change.py"):
            continue
        tree = ast.parse(path.read_text())
        called = {node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", None)
                  for node in ast.walk(tree) if isinstance(node, ast.Call)}
        assert not called & set(builders), f"{rel} calls {sorted(called & set(builders))}: use make_named_pipeline"
        names = {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}
        assert not names & {"FACTORIES", "NAMED_CHOICES", "PAPER_CHOICES", "_named_pipeline"}, rel


def test_the_table_imports_without_torch_or_sklearn():
    code = ("import sys, sklearn_hardness.models as r\n"
            "assert r.pipeline_names() and r.pipeline_info('convlstm').input == 'video'\n"
            "print(sorted(m for m in ('torch', 'sklearn', 'numpy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
