"""Crash safety: a run killed with SIGKILL resumes without repeating or losing runs."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from sklearn_hardness.experiments import run_active_sampling

from ._exp_data import TINY, tiny_presses

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

_SCRIPT = """
import sys, torch
sys.path.insert(0, {root!r})
torch.set_num_threads(1)
from tests._exp_data import TINY, tiny_presses
from tests.test_experiments_resume import EXPERIMENT
from sklearn_hardness.experiments import run_active_sampling
run_active_sampling(tiny_presses(), results_path=sys.argv[1], n_jobs=1, verbose=0, **EXPERIMENT)
"""

EXPERIMENT = dict(model="ofnn", strategies=("variance", "random"), test_classes=[0, 4],
                  n_runs=3, **dict(TINY, initial_epochs=10, epochs_per_query=5))
N_KEYS = 2 * 2 * 3


def _keys(path):
    with open(path) as f:
        return [json.dumps(json.loads(line)["key"], sort_keys=True) for line in f if line.endswith("\n")]


@pytest.mark.slow
def test_sigkill_mid_experiment_then_resume(tmp_path):
    path = tmp_path / "runs.jsonl"
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.Popen([sys.executable, "-c", _SCRIPT.format(root=ROOT), str(path)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    deadline = time.time() + 240
    try:
        while time.time() < deadline:
            if path.exists() and len(path.read_bytes().splitlines()) >= 3:
                break
            if proc.poll() is not None:
                pytest.fail("the experiment ended before it could be killed:\n" + proc.stdout.read().decode())
            time.sleep(0.05)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == -signal.SIGKILL
    done_before = _keys(path)
    assert 3 <= len(done_before) < N_KEYS, "kill should land mid-experiment"
    # the kill may land anywhere; make sure a torn last line is also handled
    complete = path.read_bytes()
    if not complete.endswith(b"\n"):
        complete = complete[: complete.rfind(b"\n") + 1]
    path.write_bytes(complete + b'{"converged":true,"accuracy":[0.5,')
    killed_pid = json.loads(complete.splitlines()[0])["pid"]

    with pytest.warns(UserWarning, match="torn"):
        res = run_active_sampling(tiny_presses(), results_path=path, n_jobs=1, verbose=0, **EXPERIMENT)
    data = path.read_bytes()
    assert data.startswith(complete)  # the runs done before the kill are kept as they were
    keys = _keys(path)
    assert len(keys) == len(set(keys)) == N_KEYS  # no duplicate, none missing
    assert len(res) == N_KEYS
    lines = [json.loads(x) for x in data.splitlines()]
    pids = [r["pid"] for r in lines]
    n_old = len(complete.splitlines())
    # runs finished before the kill were not recomputed; all others were computed now
    assert pids[:n_old] == [killed_pid] * n_old
    assert set(pids[n_old:]) == {os.getpid()}
    # and the resumed result equals a fresh computation of the same runs (seeded)
    for r in lines[:2]:
        k = r["key"]
        fresh = run_active_sampling(tiny_presses(), verbose=0, **dict(
            EXPERIMENT, strategies=(k["strategy"],), test_classes=[k["test_class"]], seeds=[k["seed"]]))
        np.testing.assert_allclose(fresh.records[0]["accuracy"], r["accuracy"])
        assert fresh.records[0]["queried"] == r["queried"]
