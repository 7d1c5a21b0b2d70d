"""Progress lines of long computations, also where the output is a file or a pipe."""

from __future__ import annotations

import contextlib
import sys
import time


def _fmt_seconds(s):
    s = int(round(s))
    return f"{s // 3600}h{s % 3600 // 60:02d}m{s % 60:02d}s" if s >= 3600 else (
        f"{s // 60}m{s % 60:02d}s" if s >= 60 else f"{s}s")


class ProgressLog:
    """One line per finished run: done/total, elapsed time and an estimate of the rest.

    Unlike a progress bar it also reports when the output is a file or a
    pipe (a batch job's log); ``verbose=0`` silences it. The estimate is the
    mean time per run finished in this call times the runs left, unless the
    caller, who may know the runs differ, passes its own to :meth:`update`.

    Parameters
    ----------
    total : int
        Runs in all (those already in the results file included).
    done : int, default=0
        Runs already finished before this call (resumed).
    desc : str, default="runs"
    verbose : int, default=1
    stream : file-like or None, default=None
        Where to write (``sys.stderr`` if None).
    unit : str, default="runs"
        What is counted, as printed.
    """

    def __init__(self, total, done=0, desc="runs", verbose=1, stream=None, unit="runs"):
        self.total, self.done, self.desc, self.verbose = int(total), int(done), desc, verbose
        self.stream, self.unit = stream, unit
        self._start = time.perf_counter()
        self._new = 0

    def update(self, n=1, seconds_left=None, note=None):
        """Count ``n`` finished runs and print a line.

        ``seconds_left``, where given, is printed as the estimate instead of
        the mean time per run times the runs left; ``note``, where given,
        follows the estimate after a comma.
        """
        self.done += n
        self._new += n
        if not self.verbose:
            return
        elapsed = time.perf_counter() - self._start
        left = self.total - self.done
        if seconds_left is not None:
            eta = seconds_left
        else:
            eta = elapsed / self._new * left if self._new else float("nan")
        self.write(f"{self.done}/{self.total} {self.unit}, {_fmt_seconds(elapsed)} elapsed, "
                   f"about {_fmt_seconds(eta)} left" + (f", {note}" if note else ""))

    def write(self, message):
        """Print ``"desc: message"`` (unless ``verbose=0``)."""
        if self.verbose:
            stream = sys.stderr if self.stream is None else self.stream
            print(f"{self.desc}: {message}", file=stream, flush=True)


class _NoBar:
    def update(self, n=1):
        pass


@contextlib.contextmanager
def progress_bar(total, desc, unit, enabled=True):
    """A :mod:`tqdm` progress bar where tqdm is installed and ``enabled``, else one that shows nothing.

    tqdm is no dependency of ours (skorch installs it): without it the
    computation runs the same, without the bar.
    """
    try:
        from tqdm.auto import tqdm
    except ImportError:
        tqdm = None
    if tqdm is None or not enabled:
        yield _NoBar()
        return
    with tqdm(total=total, desc=desc, unit=unit) as bar:
        yield bar
