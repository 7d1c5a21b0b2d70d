"""The header line of what ``evaluate`` and ``reproduce`` write: what made it, at no cost.

Command, package version, date and platform, read from the interpreter: no
benchmark, no git. The development harness (``harness/`` in the repository, not
in the wheel) adds the commit and the machine's speed reference for the studies.
"""

from __future__ import annotations

import datetime
import json
import os
import platform

from .. import __version__

_PREFIX = "# provenance "


def output_header(command, **fields):
    """One line naming what made an output: command, version, date, platform, and ``fields``.

    Parameters
    ----------
    command : str
        The command as a user would type it (``_common._reproduce_command``).
    **fields
        More keys for the record, e.g. ``config_hash``.

    Returns
    -------
    line : str
        ``"# provenance "`` and one line of JSON with the keys ``command``,
        ``version``, ``date`` (UTC), ``platform`` (system, release, machine),
        ``python`` and ``cpus`` (``os.cpu_count()``); read back with
        :func:`read_header`.

    Examples
    --------
    >>> from sklearn_hardness._cli._header import output_header, read_header
    >>> record = read_header("title\\n" + output_header("sklearn-hardness evaluate m.csv"))
    >>> record["command"], sorted(record)
    ('sklearn-hardness evaluate m.csv', ['command', 'cpus', 'date', 'platform', 'python', 'version'])
    """
    if not isinstance(command, str) or not command.strip() or "\n" in command:
        raise ValueError(f"command must be a non-empty one-line string, got {command!r}.")
    record = {
        "command": command,
        "version": __version__,
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%MZ"),
        # platform.platform() would run `uname -p` in a subprocess; these fields come from os.uname()
        "platform": f"{platform.system()}-{platform.release()}-{platform.machine()}",
        "python": platform.python_version(),
        "cpus": os.cpu_count(),
        **fields,
    }
    return _PREFIX + json.dumps(record)


def read_header(text):
    """The record of the first :func:`output_header` line in ``text``, or None where it has none."""
    for line in text.splitlines():
        if line.startswith(_PREFIX):
            return json.loads(line[len(_PREFIX):])
    return None
