"""Outputs of the command line carry what made them: command, config hash, commit, machine, date.

The header records; no test compares it with the current code (no fingerprint gate)."""

import shlex

import pytest

from sklearn_hardness._cli import build_parser
from sklearn_hardness._cli._common import _reproduce_command
from sklearn_hardness._cli._reproduce import _reproduce_config_hash
from sklearn_hardness.experiments._active import planned_config_hash
from sklearn_hardness.experiments._provenance import machine_reference, parse_provenance, provenance_header


def _command_config_hash(command):
    """What the current code computes for a recorded ``sklearn-hardness reproduce`` command."""
    words = shlex.split(command)
    assert words[:2] == ["sklearn-hardness", "reproduce"], command
    return _reproduce_config_hash(build_parser().parse_args(words[1:]))


def test_provenance_header_is_one_line_that_reads_back():
    machine = machine_reference(matmul=False)
    assert set(machine) == {"cpu", "cores", "torch_threads", "python", "torch", "numpy", "blas", "matmul_gflops",
                            "load"}
    line = provenance_header("sklearn-hardness reproduce --quick", config_hash="abc", machine=machine,
                             date="2026-01-01T00:00Z", commit="f00")
    assert "\n" not in line
    record = parse_provenance("title\n" + line + "\nbody")
    assert record == {"command": "sklearn-hardness reproduce --quick", "config_hash": "abc", "commit": "f00",
                      "machine": machine, "date": "2026-01-01T00:00Z"}
    assert parse_provenance("no header here") is None
    with pytest.raises(ValueError, match="one-line"):
        provenance_header("a\nb")


def test_machine_reference_measures_the_matmul_rate():
    gflops = machine_reference()["matmul_gflops"]
    assert isinstance(gflops, float) and 0.1 < gflops < 1e5


def test_machine_reference_names_the_kernels_blas_runs_and_what_chose_them():
    # OpenBLAS runs the kernels it picks for the CPU or those OPENBLAS_CORETYPE names; runs that refit a
    # model between choices move in their last digits with them, so the provenance says which ran
    from threadpoolctl import threadpool_info

    from sklearn_hardness.experiments._provenance import _blas

    libraries = [lib for lib in threadpool_info() if lib.get("user_api") == "blas"]
    assert libraries, "numpy and scipy load a BLAS"
    blas = machine_reference(matmul=False)["blas"]
    for lib in libraries:
        assert f"{lib['internal_api']} {lib['version']}" in blas
        if lib.get("architecture"):
            assert f"{lib['version']} {lib['architecture']}" in blas
    # the variables that steer OpenBLAS are named where set, read from the environment given
    plain = _blas(environ={})
    assert "(" not in plain and plain.startswith(blas.split(" (")[0])
    steered = _blas(environ={"OPENBLAS_CORETYPE": "Haswell", "OPENBLAS_L2_SIZE": "512", "OTHER": "1"})
    assert steered == plain + " (OPENBLAS_CORETYPE=Haswell, OPENBLAS_L2_SIZE=512)"


def test_recorded_command_leaves_out_where_output_goes():
    argv = ["reproduce", "--quick", "--out", "o", "--n-jobs", "2", "--readme=R.md", "--quiet", "--set", "a=b c"]
    assert _reproduce_command(argv) == "sklearn-hardness reproduce --quick --n-jobs 2 --set 'a=b c'"
    assert _command_config_hash("sklearn-hardness reproduce --quick --n-jobs 2") == planned_config_hash(
        "silicone5", quick=True)
    assert _command_config_hash("sklearn-hardness reproduce --quick --set n_holdout=5") != planned_config_hash(
        "silicone5", quick=True)
    assert _command_config_hash("sklearn-hardness reproduce --protocol paper") is None


