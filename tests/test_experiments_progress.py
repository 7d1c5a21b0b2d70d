"""Progress of long commands: a line per finished run, also when the output is not a terminal."""

import io
import re
import types

from sklearn_hardness.experiments import run_active_sampling
from sklearn_hardness.utils._progress import ProgressLog

from ._exp_data import TINY, tiny_presses


def test_progress_log_lines_and_estimate(monkeypatch):
    import sklearn_hardness.utils._progress as runner

    clock = iter([0.0, 10.0, 20.0, 0.0])
    monkeypatch.setattr(runner, "time", types.SimpleNamespace(perf_counter=lambda: next(clock)))
    out = io.StringIO()
    log = ProgressLog(6, done=2, desc="active sampling", stream=out)
    log.update(2)  # 2 new runs in 10 s: 5 s a run, 2 runs left
    log.update(1)
    lines = out.getvalue().splitlines()
    assert lines == ["active sampling: 4/6 runs, 10s elapsed, about 10s left",
                     "active sampling: 5/6 runs, 20s elapsed, about 7s left"]
    quiet = io.StringIO()
    ProgressLog(3, verbose=0, stream=quiet).update()
    assert quiet.getvalue() == ""


def test_experiment_prints_a_line_per_run_to_a_non_terminal(capsys, tmp_path):
    kw = dict(model="ofnn", strategies=("variance", "random"), test_classes=[0], seeds=[0, 1], n_jobs=1,
              results_path=tmp_path / "r.jsonl", **TINY)
    run_active_sampling(tiny_presses(), seeds=[0], **{k: v for k, v in kw.items() if k != "seeds"})
    err = capsys.readouterr().err  # captured: not a terminal
    assert re.findall(r"active sampling: (\d)/2 runs, \d+s elapsed, about \d+s left", err) == ["1", "2"]
    # resumed runs count as done; verbose=0 silences
    run_active_sampling(tiny_presses(), **kw)
    err = capsys.readouterr().err
    assert re.findall(r"active sampling: (\d)/4 runs", err) == ["3", "4"]
    run_active_sampling(tiny_presses(), verbose=0, **kw)
    assert capsys.readouterr().err == ""
