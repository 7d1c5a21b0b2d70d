"""Peak-memory measurement shared by the benchmarks (Linux /proc); a helper, not a benchmark.

``ru_maxrss`` only grows over a process's life; writing 5 to
``/proc/self/clear_refs`` resets the kernel's high-water mark (VmHWM), so each
measured step reports its own peak.
"""


def reset_peak():
    """Reset the resident-set high-water mark (no-op where /proc does not allow it)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass


def peak_rss_mb():
    """Peak resident set size since the last :func:`reset_peak`, in MB (NaN if unknown)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return float("nan")
