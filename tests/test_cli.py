import subprocess
import sys

import pytest

from sklearn_hardness._cli import main

from .test_manifest import _write_dataset


def test_select_command(tmp_path, capsys):
    manifest, _ = _write_dataset(tmp_path)
    assert main(["select", str(manifest), "--n-between", "1", "--plot", str(tmp_path / "c.png")]) == 0
    out = capsys.readouterr().out
    assert "contact found in 6 of 6 videos" in out
    assert (tmp_path / "c.png").stat().st_size > 1000


def test_no_command_prints_help(capsys):
    assert main([]) == 2
    assert "select" in capsys.readouterr().out


def test_console_script_is_installed():
    out = subprocess.run(
        [sys.executable, "-m", "sklearn_hardness._cli", "--version"], capture_output=True, text=True, check=True
    )
    assert out.stdout.startswith("sklearn-hardness")


def test_unknown_command():
    with pytest.raises(SystemExit):
        main(["frobnicate"])
