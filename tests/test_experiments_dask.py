"""Independent runs go through joblib, so a Dask cluster can run them."""

import numpy as np
import pytest

from sklearn_hardness.experiments import run_active_sampling

from ._exp_data import TINY, tiny_presses

distributed = pytest.importorskip("distributed")  # in the test extra


@pytest.mark.slow
def test_runs_on_a_local_dask_cluster(tmp_path):
    import joblib

    kw = dict(model="ofnn", strategies=("variance", "random"), test_classes=[1, 3], n_runs=1, verbose=0, **TINY)
    local = run_active_sampling(tiny_presses(), n_jobs=1, **kw)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        with joblib.parallel_config(backend="dask"):
            res = run_active_sampling(tiny_presses(), results_path=tmp_path / "r.jsonl", **kw)
        workers = set(client.scheduler_info()["workers"])
    assert len(workers) == 2
    assert len(res) == 4 and len(open(tmp_path / "r.jsonl").read().splitlines()) == 4
    # seeded runs give the same result wherever they run
    for a, b in zip(local.records, res.records):
        assert a["key"] == b["key"]
        np.testing.assert_allclose(a["accuracy"], b["accuracy"])
        assert a["queried"] == b["queried"]
