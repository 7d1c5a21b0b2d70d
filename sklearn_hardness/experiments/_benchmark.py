"""Time and memory of one active-sampling run (``sklearn-hardness benchmark``)."""

from __future__ import annotations

import resource
import sys
import time

import torch

from ._active import run_active_sampling
from ._config import check_config, get_config
from ._data import prepare_inputs

__all__ = ["time_active_sampling_run"]


def _peak_rss_mib():
    r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return r / 2**20 if sys.platform == "darwin" else r / 1024


def time_active_sampling_run(preset="silicone5", *, model=None, strategy="variance", test_class=0, seed=0,
                             quick=False, n_threads=None, **config):
    """Run one active-sampling run and measure it.

    The frames (and features) of all presses are prepared first and timed
    separately; then one run (``strategy``, ``test_class``, ``seed``) with
    the preset's hyperparameters is timed.

    Returns
    -------
    report : dict
        ``prepare_s``, ``run_wall_s``, ``run_cpu_s`` (all threads),
        ``peak_rss_mib`` (of this process, after the run), ``config`` and
        ``record`` (the run's record).
    """
    old = torch.get_num_threads()
    if n_threads is not None:
        torch.set_num_threads(n_threads)
    try:
        cfg = get_config(preset, quick=quick, **config)
        model = cfg["model"] if model is None else model
        cfg["model"] = model
        t = time.perf_counter()
        prepare_inputs(preset, check_config(cfg), model, verbose=0)
        prep = time.perf_counter() - t
        t, c = time.perf_counter(), time.process_time()
        res = run_active_sampling(preset, model=model, strategies=(strategy,), test_classes=[test_class],
                                  seeds=[seed], quick=quick, n_jobs=1, verbose=0, **config)
        wall, cpu = time.perf_counter() - t, time.process_time() - c
    finally:
        torch.set_num_threads(old)
    return {"prepare_s": prep, "run_wall_s": wall, "run_cpu_s": cpu, "peak_rss_mib": _peak_rss_mib(),
            "config": res.config, "record": res.records[0], "torch_threads": n_threads or old}
