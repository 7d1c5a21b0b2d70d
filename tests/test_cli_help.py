"""Every name the command line's ``--help`` texts cite is a public name of the package."""

import pytest

from sklearn_hardness._cli import _SUBCOMMANDS, main

from ._references import dangling_references


def _help(capsys, argv):
    with pytest.raises(SystemExit) as exc:
        main(argv + ["--help"])
    assert exc.value.code == 0
    return capsys.readouterr().out


def test_the_checker_finds_a_name_that_is_not_public():
    text = ("stopped by experiments.decision_stop; see sklearn_hardness.models.mc_dropout_helper, "
            "models.pipeline_info, sklearn_hardness.experiments.get_config and utils.estimator_checks; "
            "results.jsonl and docs/user_guide/runtime.rst are files, modAL.models.ActiveLearner is modAL's")
    assert dangling_references(text) == ["experiments.decision_stop", "models.mc_dropout_helper"]


@pytest.mark.parametrize("command", [[]] + [[name] for name in _SUBCOMMANDS])
def test_help_cites_only_public_names(command, capsys):
    text = _help(capsys, command)
    assert dangling_references(text) == [], (
        f"'sklearn-hardness {' '.join(command)} --help' cites names that are not public; point at the "
        "public name that holds it, or say it in words")


def test_reproduce_help_cites_names_the_checker_sees(capsys):
    # guards against a checker that passes vacuously: reproduce --help does cite public names
    assert "experiments.get_config" in " ".join(_help(capsys, ["reproduce"]).split())
