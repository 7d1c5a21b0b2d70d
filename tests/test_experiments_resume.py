"""Crash safety: a run killed with SIGKILL resumes without repeating or losing runs."""

import contextlib
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


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_signal_stops_the_workers_and_keeps_the_results(tmp_path, signum):
    import csv

    import psutil

    from sklearn_hardness.experiments._results import ResultsStore
    from sklearn_hardness.io import write_video

    data = tiny_presses()
    with open(tmp_path / "manifest.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["path", "label"])
        for i in range(len(data.videos)):
            write_video(tmp_path / f"p{i:03d}.npy", data.videos[i])
            w.writerow([f"p{i:03d}.npy", data.target_names[data.target[i]]])
    out = tmp_path / "out"
    argv = [sys.executable, "-m", "sklearn_hardness._cli", "reproduce", "--dataset", str(tmp_path / "manifest.csv"),
            "--model", "ofnn", "--n-jobs", "2", "--n-runs", "20", "--strategies", "variance", "random",
            "--out", str(out), "--quiet", "--set"] + [f"{k}={v!r}".replace(" ", "") for k, v in TINY.items()]
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""), OMP_NUM_THREADS="1")
    log = tmp_path / "stderr.txt"
    results = out / "results.jsonl"
    workers = []
    with open(log, "w") as err_file:  # a file, not a pipe: workers left running would hold a pipe open
        # a shell without job control starts background commands with SIGINT ignored, and the
        # child would inherit that (as `cmd &` users expect); the test is about a foreground
        # run, so the child starts with the default disposition
        proc = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=err_file,
                                preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.time() + 240
    try:
        while not (results.exists() and results.read_bytes().count(b"\n") >= 2):
            if proc.poll() is not None or time.time() > deadline:
                pytest.fail("the experiment ended before the signal:\n" + log.read_text())
            time.sleep(0.05)
        workers = psutil.Process(proc.pid).children(recursive=True)
        assert workers, "runs should go to worker processes"
        proc.send_signal(signum)
        proc.wait(timeout=60)
        _, alive = psutil.wait_procs(workers, timeout=30)  # generous: a loaded machine reaps slowly
        assert [p for p in alive if p.status() != psutil.STATUS_ZOMBIE] == []
    finally:
        for p in [proc, *workers]:  # never leave processes behind, even when the test fails
            with contextlib.suppress(psutil.NoSuchProcess, ProcessLookupError):
                p.kill()
    assert proc.returncode == 128 + signum
    assert log.read_text().strip().endswith("rerun the same command to resume"), log.read_text()
    store = ResultsStore(results)  # every line a complete run, none torn
    assert store.n_torn == 0 and 2 <= len(store.records) < 2 * 5 * 20
