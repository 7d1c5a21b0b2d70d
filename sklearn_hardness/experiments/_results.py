"""A resumable, append-only results file (JSON Lines) and the result container.

Every finished run is one line: a JSON object with a ``"key"`` (what was run:
experiment, strategy or model, test class, seed, config hash) and its
metrics. A line is written with a single ``write`` of the whole line, then
flushed and ``fsync``-ed, so after a crash or ``kill -9`` the file holds every
run that finished, plus at most one torn last line (no final newline, or not
valid JSON). :class:`ResultsStore` detects that line, warns, and truncates it
before appending, so a rerun of the same command skips the finished keys and
computes only the missing ones.
"""

from __future__ import annotations

import contextlib
import json
import os
import warnings

import numpy as np

from ..utils._json import to_json
from ..utils._warnings import external_stacklevel

__all__ = ["ResultsStore", "ExperimentResult", "key_id"]


def key_id(key):
    """A string id of a run key (dict): ``"name=value|..."`` in sorted order."""
    return "|".join(f"{k}={key[k]}" for k in sorted(key))


class ResultsStore:
    """Append-only JSON Lines file of finished runs, safe against crashes.

    Parameters
    ----------
    path : str or path-like or None
        The file; created (with its folder) if missing. ``None`` keeps the
        records in memory only (nothing is resumed).

    Attributes
    ----------
    records : list of dict
        The runs read from the file plus those appended since.
    n_torn : int
        Torn lines found (and removed) when the file was opened.

    Notes
    -----
    Only one process may write a file at a time: while an experiment runs
    it holds an exclusive ``fcntl`` lock on ``path + ".lock"`` (POSIX), and a
    second process trying to write the same file gets a clear error instead
    of duplicating runs.
    """

    def __init__(self, path):
        self.path = None if path is None else os.fspath(path)
        self.records = []
        self.n_torn = 0
        self._ids = set()
        self._lock_file = None
        if self.path is not None:
            self._load()

    def _load(self):
        self.records, self._ids, self.n_torn = [], set(), 0
        self._needs_newline = False
        if not os.path.exists(self.path):
            return
        with open(self.path, "rb") as f:
            data = f.read()
        good_end = 0  # byte offset after the last complete, valid line
        pos = 0
        lines = data.split(b"\n")
        for i, raw in enumerate(lines):
            last = i == len(lines) - 1
            end = pos + len(raw) + (0 if last else 1)
            if raw.strip():
                try:
                    rec = json.loads(raw)
                except ValueError:
                    rec = None
                if isinstance(rec, dict) and "key" in rec and not isinstance(rec["key"], dict):
                    # complete JSON, so not a torn write: a line some other program wrote
                    raise ValueError(
                        f"{self.path}: line {i + 1} is a record whose 'key' is a "
                        f"{type(rec['key']).__name__}, not a dict of what was run; the file was not "
                        "written by this library alone. Fix or remove that line."
                    )
                if not isinstance(rec, dict) or "key" not in rec:
                    if last or all(not rest.strip() for rest in lines[i + 1 :]):
                        # the torn tail of an interrupted write
                        self.n_torn += 1
                        break
                    raise ValueError(
                        f"{self.path}: line {i + 1} is not a valid run record and is followed "
                        "by more lines; the file was not written by this library alone. Fix or "
                        "remove that line."
                    ) from None
                if last:  # valid JSON but no final newline: written completely, keep it
                    self._add(rec)
                    good_end = end
                    self._needs_newline = True
                    break
                self._add(rec)
            good_end = end
            pos = end
        if self.n_torn:
            warnings.warn(
                f"{self.path}: ignoring a torn last line (an interrupted write); "
                f"{len(self.records)} complete runs kept, the torn line is removed.",
                UserWarning,
                stacklevel=external_stacklevel(),
            )
            with open(self.path, "r+b") as f:
                f.truncate(good_end)
                f.flush()
                os.fsync(f.fileno())

    def _add(self, rec):
        kid = key_id(rec["key"])
        if kid in self._ids:
            warnings.warn(
                f"{self.path}: duplicate run {kid}; the first one is kept.", UserWarning,
                stacklevel=external_stacklevel(),
            )
            return
        self._ids.add(kid)
        self.records.append(rec)

    def __contains__(self, key):
        return key_id(key) in self._ids

    def __len__(self):
        return len(self.records)

    @contextlib.contextmanager
    def writing(self):
        """Hold the writer lock for the duration of an experiment."""
        if self.path is None:
            yield self
            return
        folder = os.path.dirname(os.path.abspath(self.path))
        os.makedirs(folder, exist_ok=True)
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX
            yield self
            return
        lock = open(self.path + ".lock", "a")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            lock.close()
            raise RuntimeError(
                f"another process is writing {self.path} (lock {self.path}.lock is held); "
                "wait for it to finish or use another results path."
            ) from None
        try:
            self._load()  # what other processes wrote before we got the lock
            yield self
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
            lock.close()

    def append(self, record):
        """Add a finished run; with a file, write it durably (one line, fsync)."""
        record = to_json(record)
        if record["key"] in self:
            raise ValueError(f"run {key_id(record['key'])} is already in the results.")
        if self.path is not None:
            line = json.dumps(record, separators=(",", ":"), allow_nan=False) + "\n"
            if getattr(self, "_needs_newline", False):
                line = "\n" + line
                self._needs_newline = False
            fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
            try:
                buf = line.encode()
                while buf:  # os.write may write less than asked
                    n = os.write(fd, buf)
                    buf = buf[n:]
                os.fsync(fd)
            finally:
                os.close(fd)
        self._ids.add(key_id(record["key"]))
        self.records.append(record)


class ExperimentResult:
    """Records of an experiment's runs, with helpers to aggregate them.

    Parameters
    ----------
    records : list of dict
        One dict per run (the lines of the results file).
    config : dict or None
        The configuration the runs were made with.
    path : str or None
        The results file, if any.

    Attributes
    ----------
    records : list of dict
        Tidy: one dict per run, per-iteration metrics as lists.
        ``pandas.DataFrame(result.records)`` gives a table.

    Examples
    --------
    >>> from sklearn_hardness.experiments import ExperimentResult
    >>> runs = [{"key": {"strategy": s, "seed": 0}, "accuracy": [0.4, a], "converged": True}
    ...         for s, a in [("variance", 0.8), ("random", 0.6)]]
    >>> res = ExperimentResult(runs)
    >>> res.groups("strategy"), res.curves("accuracy", strategy="variance").tolist()
    (['variance', 'random'], [[0.4, 0.8]])
    """

    def __init__(self, records, config=None, path=None):
        self.records = list(records)
        self.config = config
        self.path = path

    def __len__(self):
        return len(self.records)

    def __iter__(self):
        return iter(self.records)

    def __repr__(self):
        return f"ExperimentResult(n_runs={len(self.records)}, path={self.path!r})"

    def groups(self, field):
        """Distinct values of ``record["key"][field]`` in first-seen order."""
        out = []
        for r in self.records:
            v = r["key"].get(field)
            if v not in out:
                out.append(v)
        return out

    def select(self, converged_only=True, **key_values):
        """Records whose key matches ``key_values`` (and that converged)."""
        out = []
        for r in self.records:
            if converged_only and not r.get("converged", True):
                continue
            if all(r["key"].get(k) == v for k, v in key_values.items()):
                out.append(r)
        return out

    def curves(self, metric, converged_only=True, **key_values):
        """Stack a per-iteration metric: array (n_runs, n_iterations + 1).

        Runs that stopped early (not converged) are left out when
        ``converged_only``; otherwise their missing iterations are NaN.
        """
        rows = [r[metric] for r in self.select(converged_only, **key_values)]
        if not rows:
            return np.empty((0, 0))
        width = max(len(np.atleast_1d(r)) for r in rows)
        out = np.full((len(rows), width), np.nan)
        for i, r in enumerate(rows):
            r = np.atleast_1d(np.asarray(r, dtype=float))
            out[i, : len(r)] = r
        return out

    def converged_fraction(self, **key_values):
        """Fraction of runs (matching ``key_values``) that converged."""
        rows = self.select(False, **key_values)
        if not rows:
            return float("nan")
        return float(np.mean([bool(r.get("converged", True)) for r in rows]))

    def to_frame(self):
        """The records as a ``pandas.DataFrame`` (pandas is optional)."""
        try:
            import pandas as pd
        except ImportError as exc:  # pragma: no cover
            raise ImportError("to_frame() needs pandas: pip install pandas") from exc
        rows = []
        for r in self.records:
            row = dict(r["key"])
            row.update({k: v for k, v in r.items() if k != "key"})
            rows.append(row)
        return pd.DataFrame(rows)

    # -- tables -------------------------------------------------------------------------------------

    def comparison_table(self, iteration=-1, human=True):
        """Rows of the paper's Table I: no resampling, each strategy, humans (paper).

        Parameters
        ----------
        iteration : int, default=-1
            Which iteration the strategies are compared at (-1: the last, N).
        human : bool, default=True
            Add the paper's human accuracy (48.00% +- 22.27%) as a reference row.

        Returns
        -------
        rows : list of dict
            ``name``, ``accuracy_mean``, ``accuracy_std``, ``mae_mean``,
            ``mae_std``, ``n_runs`` (converged runs used), ``n_total`` and
            ``converged_fraction``; accuracy as a fraction. "no resampling" is
            iteration 0 (after the initial training) of the converged runs, once
            per (test object, seed), as the initial training is shared by the
            strategies. ``pandas.DataFrame(rows)`` takes them;
            :meth:`format_table` writes them as text.

        Examples
        --------
        >>> from sklearn_hardness.experiments import ExperimentResult
        >>> runs = [{"key": {"experiment": "active_sampling", "strategy": s, "test_class": 0, "seed": k},
        ...          "converged": True, "accuracy": [0.4, a], "mae": [0.2, 0.1]}
        ...         for k in range(2) for s, a in (("variance", 0.8), ("random", 0.6))]
        >>> res = ExperimentResult(runs)
        >>> [(r["name"], r["accuracy_mean"]) for r in res.comparison_table(human=False)]
        [('no resampling', 0.4), ('variance', 0.8), ('random', 0.6)]
        """
        from ._tables import comparison_table

        return comparison_table(self, iteration=iteration, human=human)

    def baseline_table(self):
        """Rows per model (baselines) or per dropout rate (sweep): mean +- std of the metrics.

        For the results of :func:`~sklearn_hardness.experiments.run_model_baselines`
        and :func:`~sklearn_hardness.experiments.run_dropout_sweep`.

        Returns
        -------
        rows : list of dict
            ``name`` (the model, or the dropout rate), ``train_accuracy_mean``,
            ``train_accuracy_std``, ``accuracy_mean``, ``accuracy_std``,
            ``mae_mean``, ``mae_std``, ``n_runs`` and ``converged_fraction``;
            :meth:`format_table` writes them as text.

        Examples
        --------
        ::

            from sklearn_hardness.experiments import run_model_baselines

            res = run_model_baselines("silicone5", quick=True)
            print(res.format_table(res.baseline_table(), mae_unit="mm/N"))
        """
        from ._tables import baseline_table

        return baseline_table(self)

    @staticmethod
    def format_table(rows, mae_unit=None):
        """Plain-text table of :meth:`comparison_table` or :meth:`baseline_table` rows.

        Parameters
        ----------
        rows : list of dict
            The rows (a subset of them, or rows of several results, as well).
        mae_unit : str or None, default=None
            The hardness unit, written beside the MAE column's title.

        Returns
        -------
        text : str

        Examples
        --------
        >>> from sklearn_hardness.experiments import ExperimentResult
        >>> print(ExperimentResult.format_table([{"name": "random", "accuracy_mean": 0.8, "accuracy_std": 0.1,
        ...       "mae_mean": 0.05, "mae_std": 0.02, "n_runs": 4, "n_total": 5, "converged_fraction": 0.8}]))
                accuracy           MAE             runs  converged
        ------  -----------------  --------------  ----  ---------
        random   80.00% +- 10.00%  0.050 +- 0.020  4/5   80%
        """
        from ._tables import format_table

        return format_table(rows, mae_unit=mae_unit)

    def paired_table(self, reference="random", metrics=None, level=0.95):
        """Per strategy and metric: mean with its interval, and the paired difference to ``reference``.

        For the results of :func:`~sklearn_hardness.experiments.run_active_sampling`.

        Parameters
        ----------
        reference : str, default="random"
            The strategy every other one is compared with.
        metrics : sequence of str or None, default=None
            Among ``"presses_at_stop"``, ``"accuracy_at_stop"`` (the reference
            presses used, and the test accuracy, when the run's decision is
            settled: at least 80% of the test presses voting for the same class
            for 2 iterations), ``"accuracy"``,
            ``"holdout_accuracy"`` (after the press budget, on the test
            object's presses and on held-out presses of the other objects),
            ``"auc"`` (the mean accuracy over iterations 0..N, in [0, 1]: a
            strategy that gets there sooner scores higher), ``"mae"`` and
            ``"holdout_mae"``. None: all whose fields the records have.
        level : float, default=0.95
            Confidence level of the t-intervals.

        Returns
        -------
        rows : list of dict
            ``strategy``, ``metric``, ``n`` (converged runs), ``mean``, ``ci_low``,
            ``ci_high`` (t-interval of the mean over runs), and for strategies other
            than the reference ``n_pairs`` (pairs where both runs converged),
            ``diff`` (mean of strategy minus reference), ``diff_low``, ``diff_high``
            (t-interval over pairs), ``p_ttest`` (paired t-test) and ``p_wilcoxon``
            (Wilcoxon signed-rank; 1.0 when every difference is 0).
            :meth:`format_paired_table` writes them as text.

        Examples
        --------
        >>> from sklearn_hardness.experiments import ExperimentResult
        >>> recs = [{"key": {"strategy": s, "test_class": 0, "seed": k}, "converged": True,
        ...          "accuracy": [0.2, a], "mae": [0.1, 0.0]}
        ...         for k in range(4) for s, a in (("random", 0.4 + 0.1 * k), ("variance", 0.6 + 0.1 * k))]
        >>> row = [r for r in ExperimentResult(recs).paired_table() if r["strategy"] == "variance"][0]
        >>> round(row["diff"], 3), row["n_pairs"], row["p_ttest"] < 0.05
        (0.2, 4, True)
        """
        from ._stats import paired_table

        return paired_table(self, reference=reference, metrics=metrics, level=level)

    @staticmethod
    def format_paired_table(rows, reference="random"):
        """Plain-text table of :meth:`paired_table` rows (accuracies in %).

        An interval over fewer than 5 runs or pairs is said in words
        (``"3 pairs: too few for an interval"``).

        Parameters
        ----------
        rows : list of dict
        reference : str, default="random"
            The strategy the rows were paired with (named in the column titles).

        Returns
        -------
        text : str

        Examples
        --------
        ::

            from sklearn_hardness.experiments import run_active_sampling

            res = run_active_sampling("silicone5", strategies=("thompson", "random"), quick=True, n_jobs=2)
            print(res.format_paired_table(res.paired_table(reference="random")))
        """
        from ._stats import format_paired_table

        return format_paired_table(rows, reference=reference)

    def presses_to_reach(self, reference="random", *, n_boot=2000, level=0.95, random_state=0):
        """Reference presses each strategy needs to reach the reference's final accuracy.

        The paper always presses ``n_initial + N * n_per_query`` reference
        objects. A strategy whose mean accuracy on the test presses (over the
        paired runs) reaches the reference strategy's mean *final* accuracy after
        fewer iterations gets there with fewer presses. Intervals come from a
        bootstrap over the (test object, seed) pairs, resampling the strategy's
        runs and the reference's runs of the same pairs together.

        Parameters
        ----------
        reference : str, default="random"
            Whose final accuracy is the target (a strategy of the runs).
        n_boot : int, default=2000
            Bootstrap resamples of the pairs.
        level : float, default=0.95
            Level of the percentile intervals.
        random_state : int, default=0
            Seed of the bootstrap.

        Returns
        -------
        rows : list of dict
            One per strategy (the reference too): ``strategy``, ``n_pairs``
            (pairs where both runs converged), ``target`` (the reference's mean
            final accuracy over those pairs), ``curve`` (mean accuracy after each
            iteration), ``presses`` (after each iteration), ``presses_to_reach``
            (the first press count whose mean accuracy is at least ``target``;
            inf if it never does), ``ci_low``, ``ci_high`` (bootstrap percentiles;
            inf when the strategy did not reach the target in more than
            ``(1 - level) / 2`` of the resamples), ``p_reached`` (fraction of
            resamples in which it reached the target), and for strategies other
            than the reference ``diff``, ``diff_low``, ``diff_high`` (presses minus
            the reference's own presses to reach its final accuracy, over the same
            resamples; below 0: fewer presses). :meth:`format_presses_to_reach`
            writes them as text.

        Examples
        --------
        >>> from sklearn_hardness.experiments import ExperimentResult
        >>> recs = [{"key": {"strategy": s, "test_class": 0, "seed": k}, "converged": True,
        ...          "initial_indices": [0] * 10, "drawn_indices": [[0] * 5] * 2, "accuracy": acc}
        ...         for k in range(6) for s, acc in (("random", [0.2, 0.4, 0.8]), ("variance", [0.2, 0.8, 0.8]))]
        >>> rows = ExperimentResult(recs).presses_to_reach(n_boot=200)
        >>> [(r["strategy"], float(r["presses_to_reach"])) for r in rows]
        [('random', 20.0), ('variance', 15.0)]
        """
        from ._stats import presses_to_reach

        return presses_to_reach(self, reference=reference, n_boot=n_boot, level=level, random_state=random_state)

    @staticmethod
    def format_presses_to_reach(rows, reference="random"):
        """Plain-text table of :meth:`presses_to_reach` rows.

        Parameters
        ----------
        rows : list of dict
        reference : str, default="random"
            The strategy whose final accuracy was the target.

        Returns
        -------
        text : str

        Examples
        --------
        ::

            print(res.format_presses_to_reach(res.presses_to_reach()))  # res: run_active_sampling's
        """
        from ._stats import format_presses_to_reach

        return format_presses_to_reach(rows, reference=reference)

    # -- figures (matplotlib: the "plot" extra) ----------------------------------------------------

    def plot_active_sampling(self, metric="accuracy", ax=None, band="std"):
        """Mean of a per-iteration metric per strategy, with a +-1 std band (Figs. 5, 7).

        For the results of :func:`~sklearn_hardness.experiments.run_active_sampling`
        (converged runs are used).

        Parameters
        ----------
        metric : {"accuracy", "mae", "entropy", "variance", "bald"}, default="accuracy"
        ax : matplotlib Axes or None, default=None
            Where to draw (None: a new figure).
        band : {"std", "sem", None}, default="std"
            Shaded band: standard deviation over runs (as the paper), standard
            error of the mean, or none.

        Returns
        -------
        ax : matplotlib Axes

        Examples
        --------
        Needs matplotlib (``pip install "sklearn-hardness[plot]"``)::

            from sklearn_hardness.experiments import run_active_sampling

            res = run_active_sampling("silicone5", quick=True, n_jobs=2)
            res.plot_active_sampling(metric="accuracy").figure.savefig("accuracy.png")
        """
        from ._plotting import plot_active_sampling

        return plot_active_sampling(self, metric=metric, ax=ax, band=band)

    def plot_uncertainty(self, kind="entropy", ax=None):
        """Mean per-class entropy or variance on the test presses per iteration (Figs. 6, 8).

        Parameters
        ----------
        kind : {"entropy", "variance", "bald"}, default="entropy"
        ax : matplotlib Axes or None, default=None
            Where to draw (None: a new figure).

        Returns
        -------
        ax : matplotlib Axes

        Examples
        --------
        Needs matplotlib::

            res.plot_uncertainty(kind="variance").figure.savefig("variance.png")  # res: run_active_sampling's
        """
        from ._plotting import plot_uncertainty

        return plot_uncertainty(self, kind=kind, ax=ax)

    def plot_dropout_sweep(self, metric="accuracy", ax=None, smooth=5):
        """Mean and std of a metric against the dropout rate, Savitzky-Golay smoothed (Fig. 4).

        For the results of :func:`~sklearn_hardness.experiments.run_dropout_sweep`.

        Parameters
        ----------
        metric : {"accuracy", "mae"}, default="accuracy"
        ax : matplotlib Axes or None, default=None
            Where to draw (None: a new figure).
        smooth : int or None, default=5
            Window of :func:`scipy.signal.savgol_filter` (order 2) for the curves;
            the raw means are drawn as dots. None: no smoothing.

        Returns
        -------
        ax : matplotlib Axes

        Examples
        --------
        Needs matplotlib::

            from sklearn_hardness.experiments import run_dropout_sweep

            run_dropout_sweep("silicone5", quick=True).plot_dropout_sweep().figure.savefig("dropout.png")
        """
        from ._plotting import plot_dropout_sweep

        return plot_dropout_sweep(self, metric=metric, ax=ax, smooth=smooth)

    def plot_model_baselines(self, ax=None):
        """Bar chart of train and test accuracy per model with std error bars (Fig. 3).

        Parameters
        ----------
        ax : matplotlib Axes or None, default=None
            Where to draw (None: a new figure).

        Returns
        -------
        ax : matplotlib Axes

        Examples
        --------
        Needs matplotlib::

            from sklearn_hardness.experiments import run_model_baselines

            run_model_baselines("silicone5", quick=True).plot_model_baselines().figure.savefig("baselines.png")
        """
        from ._plotting import plot_model_baselines

        return plot_model_baselines(self, ax=ax)

    def save_figures(self, out_dir, prefix=""):
        """Write the figures of this result as PNG files; return their paths.

        Active sampling: ``accuracy.png``, ``mae.png``, ``entropy.png``,
        ``variance.png``; baselines: ``baselines.png``; dropout sweep:
        ``dropout_accuracy.png``, ``dropout_mae.png``.

        Parameters
        ----------
        out_dir : str or path-like
            The folder (made if missing).
        prefix : str, default=""
            Put before each file's name.

        Returns
        -------
        paths : list of str

        Examples
        --------
        Needs matplotlib::

            from sklearn_hardness.experiments import run_active_sampling

            paths = run_active_sampling("silicone5", quick=True).save_figures("figures")
        """
        from ._plotting import save_figures

        return save_figures(self, out_dir, prefix=prefix)
