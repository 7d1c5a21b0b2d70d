"""The experiments' named models are the registry's named pipelines, taken apart."""

import numpy as np
import pytest

from sklearn_hardness.experiments import get_config
from sklearn_hardness.experiments._config import check_config
from sklearn_hardness.experiments._data import _feature_params, _frame_params
from sklearn_hardness.experiments._models import MODEL_NAMES, make_estimator, model_pipeline
from sklearn_hardness.models import make_named_pipeline, pipeline_info

THREE = ["log_peak_change", "log_loading_time", "log_contact_spread"]


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_the_run_s_net_is_the_named_pipeline_s_classifier(name):
    cfg = check_config(get_config("silicone5", model=name))
    net = make_estimator(name, cfg, seed=3, n_classes=5)
    clf = make_named_pipeline(name).named_steps["clf"]
    assert type(net) is type(clf)
    # what a run sets (the paper's settings, its seed and classes) on top of the named pipeline's net
    run_params = {"dropout", "lr", "random_state", "classes", "max_epochs", "device", "batch_size",
                  "dropout_placement", "callbacks", "class_weight"}
    theirs, ours = clf.get_params(deep=False), net.get_params(deep=False)
    assert {k: v for k, v in ours.items() if k not in run_params} == \
        {k: v for k, v in theirs.items() if k not in run_params}
    assert net.random_state == 3 and net.class_weight is None  # the paper's unweighted loss
    if pipeline_info(name).random:  # a net; a logistic regression learns its classes
        np.testing.assert_array_equal(net.classes, np.arange(5))


def test_frame_and_feature_steps_come_from_the_named_pipelines():
    # the values of the inputs cached before the factories built them: cached frames stay valid
    expected = {"convlstm": ((12, 16), "gray", True), "ofnn": ((120, 160), "gray", False),
                "dinov2nn": ((112, 150), "rgb", True)}
    for name, (size, color, subtract_first) in expected.items():
        cfg = check_config(get_config("silicone5", model=name))
        assert _frame_params(cfg, name) == {"n_between": 2, "output_size": size, "color": color,
                                            "subtract_first": subtract_first}
        selector = model_pipeline(name, cfg).named_steps["frames"]
        assert selector.frame_size == size and selector.color == color
    cfg = check_config(get_config("silicone5", model="contact_profile_nn"))
    assert _frame_params(cfg, "contact_profile_nn") is None
    assert _feature_params(cfg, "contact_profile_nn") == {"kind": "contact_profile", "max_side": 80}
    assert _feature_params(cfg, "contact_profile") == {"kind": "contact_profile", "max_side": 80}
    assert _feature_params(cfg, "contact_profile_3") == {"kind": "contact_profile", "max_side": 80,
                                                         "features": THREE}
    assert _frame_params(cfg, "loading_compliance") is None
    assert _feature_params(cfg, "loading_compliance") == {"kind": "loading_compliance",
                                                           "features": ["hertz_compliance"],
                                                          "onset": 0.1, "drive_compliance": 0.0}
    assert _feature_params(check_config(get_config("shore9", model="ofnn")), "ofnn") == \
        {"kind": "optical_flow", "n_features": 500}
    # the experiments reproduce the paper: OFNN on flattened tracks, the ConvLSTM on frames alone
    assert model_pipeline("ofnn", cfg).named_steps["features"].output == "tracks"
    assert "intensity" not in model_pipeline("convlstm", cfg).named_steps


def test_config_input_settings_reach_the_frames_step():
    cfg = check_config(get_config("silicone5", frame_size=(18, 24), color="rgb", crop_contact=0.5))
    assert _frame_params(cfg, "convlstm") == {"n_between": 2, "output_size": (18, 24), "color": "rgb",
                                              "subtract_first": True, "crop_contact": 0.5}
    # any estimator gets the ConvLSTM's frames
    assert _frame_params(cfg, object()) == _frame_params(cfg, "convlstm")


def test_frame_size_is_checked_by_one_rule():
    from sklearn_hardness.preprocessing import ContactFrameSelector

    for bad in [(1, 16), (12,), "12x16", (12.0, 16), (True, 16)]:
        with pytest.raises(ValueError, match="'frame_size' parameter .* pair \\(height, width\\)"):
            check_config(get_config("silicone5", frame_size=bad))
        with pytest.raises(ValueError, match="'frame_size' parameter .* pair \\(height, width\\)"):
            ContactFrameSelector(frame_size=bad).fit([np.zeros((4, 8, 8, 3), np.uint8)])


def test_contact_profile_3_reads_three_of_the_twelve_features():
    """The named model's inputs are the three columns of the twelve, from the same videos."""
    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.experiments._data import prepare_inputs
    from sklearn_hardness.features._contact_profile import FEATURE_NAMES

    data = make_presses("everyday", n_per_class=2, n_objects=6, class_ratio=[1, 1, 1], image_size=(32, 40),
                        codec=None, random_state=0)
    twelve = prepare_inputs(data, check_config(get_config("silicone5", model="contact_profile")), "contact_profile",
                            memory=False, verbose=0)
    three = prepare_inputs(data, check_config(get_config("silicone5", model="contact_profile_3")), "contact_profile_3",
                           memory=False, verbose=0)
    assert twelve.X.shape == (12, 12) and three.X.shape == (12, 3)
    np.testing.assert_array_equal(three.X, twelve.X[:, [FEATURE_NAMES.index(f) for f in THREE]])
    np.testing.assert_array_equal(three.y, twelve.y)
    pipe = model_pipeline("contact_profile_3", check_config(get_config("silicone5", model="contact_profile_3")))
    assert list(pipe.named_steps["features"].features) == THREE and pipe.named_steps["clf"].class_weight is None
