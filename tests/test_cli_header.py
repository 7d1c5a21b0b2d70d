"""Outputs of ``evaluate`` and ``reproduce`` start with a cheap header: command, version, date, platform.

The header records what made an output, read from the interpreter; the commit and
the machine's speed reference are the development harness's (tests/test_harness.py).
"""

import os
import re
import subprocess
import sys

import pytest

from sklearn_hardness import __version__
from sklearn_hardness._cli._common import _reproduce_command
from sklearn_hardness._cli._header import output_header, read_header


def test_output_header_is_one_line_that_reads_back():
    line = output_header("sklearn-hardness reproduce --quick", config_hash="abc")
    assert "\n" not in line and line.startswith("# provenance ")
    record = read_header("title\n" + line + "\nbody")
    assert set(record) == {"command", "version", "date", "platform", "python", "cpus", "config_hash"}
    assert record["command"] == "sklearn-hardness reproduce --quick" and record["config_hash"] == "abc"
    assert record["version"] == __version__ and record["cpus"] == os.cpu_count()
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\dZ", record["date"])
    assert record["platform"].startswith(os.uname().sysname) and re.fullmatch(r"3\.\d+\.\d+.*", record["python"])
    assert read_header("no header here") is None
    with pytest.raises(ValueError, match="one-line"):
        output_header("a\nb")


def test_output_header_runs_no_subprocess():
    # no git, no `uname -p` (platform.platform() would run it): the header is read from the interpreter,
    # in a fresh one here, where nothing is cached yet
    code = ("import os, subprocess\n"
            "def refuse(*args, **kwargs):\n"
            "    raise SystemExit(f'the header started a process: {args}')\n"
            "subprocess.Popen.__init__ = os.posix_spawn = refuse\n"
            "from sklearn_hardness._cli._header import output_header\n"
            "print(output_header('sklearn-hardness evaluate m.csv'))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert read_header(out.stdout)["command"] == "sklearn-hardness evaluate m.csv"


def test_recorded_command_leaves_out_where_output_goes():
    argv = ["reproduce", "--quick", "--out", "o", "--n-jobs", "2", "--out=p", "--quiet", "--set", "a=b c"]
    assert _reproduce_command(argv) == "sklearn-hardness reproduce --quick --n-jobs 2 --set 'a=b c'"
