"""Peak resident memory, of this process or of a process tree (Linux /proc, psutil).

``ru_maxrss`` only grows over a process's life; writing 5 to
``/proc/self/clear_refs`` resets the kernel's high-water mark (VmHWM), so each
measured step reports its own peak. Elsewhere :func:`peak_rss_mb` falls back on
``ru_maxrss`` (the peak over the process's life).
"""

from __future__ import annotations

import resource
import sys
import threading

__all__ = ["reset_peak", "peak_rss_mb", "TreePeak"]


def reset_peak():
    """Reset the resident-set high-water mark of this process (no-op where /proc does not allow it)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass


def _maxrss_mb(who):
    kib = resource.getrusage(who).ru_maxrss
    return kib / 2**20 if sys.platform == "darwin" else kib / 1024  # macOS reports bytes, Linux KiB


def peak_rss_mb(children=False):
    """Peak resident set size in MiB: of this process since :func:`reset_peak`, or of its children.

    Parameters
    ----------
    children : bool, default=False
        The largest peak of the child processes waited for (``RUSAGE_CHILDREN``)
        instead of this process's.

    Returns
    -------
    mb : float

    Examples
    --------
    >>> from harness.memory import peak_rss_mb, reset_peak
    >>> reset_peak()
    >>> peak_rss_mb() > 0
    True
    """
    if children:
        return _maxrss_mb(resource.RUSAGE_CHILDREN)
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return _maxrss_mb(resource.RUSAGE_SELF)


class TreePeak:
    """The peak resident memory of a process and all its descendants, sampled in a thread.

    joblib's workers count too; a sample every ``interval`` seconds can miss a
    shorter spike, so read it beside the process's own ``ru_maxrss``.

    Parameters
    ----------
    pid : int
        The root process.
    interval : float, default=0.2
        Seconds between samples.

    Examples
    --------
    >>> import os
    >>> from harness.memory import TreePeak
    >>> with TreePeak(os.getpid()) as tree:
    ...     pass
    >>> tree.peak_mb > 0
    True
    """

    def __init__(self, pid, interval=0.2):
        self.pid = pid
        self.interval = interval
        self.peak_mb = 0.0

    def _sample(self):
        import psutil

        try:
            procs = [self._root, *self._root.children(recursive=True)]
        except psutil.Error:
            return
        total = 0
        for p in procs:
            try:
                total += p.memory_info().rss
            except psutil.Error:
                pass
        self.peak_mb = max(self.peak_mb, total / 2**20)

    def _run(self):
        while not self._done.wait(self.interval):
            self._sample()

    def __enter__(self):
        import psutil

        self._root = psutil.Process(self.pid)
        self._done = threading.Event()
        self._sample()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._done.set()
        self._thread.join()
        return False
