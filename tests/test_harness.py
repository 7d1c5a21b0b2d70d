"""The development harness (``harness/`` at the repository root, not in the wheel).

pytest puts the repository root on ``sys.path`` (``tests/`` is a package), so the
harness is imported from this checkout, as the studies and benchmarks import it.
"""

import mmap
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import harness
from harness.config_hash import planned_config_hash
from harness.machine import blas_kernels, describe, machine_reference
from harness.memory import TreePeak, peak_rss_mb, reset_peak
from harness.provenance import git_commit, header, provenance_record, script_command, stamp, write_output


def test_the_harness_is_this_checkout_s_and_outside_the_package():
    import sklearn_hardness

    assert harness.ROOT == os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    assert not os.path.abspath(harness.__file__).startswith(os.path.dirname(sklearn_hardness.__file__))


# --- machine -------------------------------------------------------------------------------------


def test_machine_reference_measures_the_matmul_rate():
    machine = machine_reference()
    assert set(machine) == {"cpu", "cores", "torch_threads", "python", "torch", "numpy", "blas", "matmul_gflops",
                            "load"}
    assert isinstance(machine["matmul_gflops"], float) and 0.1 < machine["matmul_gflops"] < 1e5
    assert machine["cores"] == os.cpu_count()
    assert f"matmul {machine['matmul_gflops']:.0f} GFLOP/s (one thread)" in describe(machine)


def test_blas_kernels_names_the_kernels_and_what_chose_them():
    # OpenBLAS runs the kernels it picks for the CPU or those OPENBLAS_CORETYPE names; runs that refit a
    # model between choices move in their last digits with them, so the machine says which ran
    from threadpoolctl import threadpool_info

    libraries = [lib for lib in threadpool_info() if lib.get("user_api") == "blas"]
    assert libraries, "numpy and scipy load a BLAS"
    plain = blas_kernels(environ={})
    for lib in libraries:
        assert f"{lib['internal_api']} {lib['version']}" in plain
        if lib.get("architecture"):
            assert f"{lib['version']} {lib['architecture']}" in plain
    steered = blas_kernels(environ={"OPENBLAS_CORETYPE": "Haswell", "OPENBLAS_L2_SIZE": "512", "OTHER": "1"})
    assert "(" not in plain and steered == plain + " (OPENBLAS_CORETYPE=Haswell, OPENBLAS_L2_SIZE=512)"


def test_machine_reference_in_another_environment_is_read_there():
    # the kernels a child process ran under its environment are only seen in a process with that environment
    env = dict(os.environ, OPENBLAS_L2_SIZE="512")
    machine = machine_reference(matmul=False, env=env)
    assert machine["matmul_gflops"] is None and machine["cores"] == os.cpu_count()
    assert machine["blas"].endswith("OPENBLAS_L2_SIZE=512)")


# --- provenance ----------------------------------------------------------------------------------


def test_git_commit_names_head_or_nothing(tmp_path):
    commit = git_commit()  # None where git is not installed
    assert commit is None or re.fullmatch(r"[0-9a-f]{10}( \(uncommitted changes\))?", commit)
    assert git_commit(str(tmp_path)) is None  # not a repository


def test_script_command_is_what_a_reader_types_from_the_root():
    script = os.path.join(harness.ROOT, "studies", "scripts", "sim_confounds.py")
    argv = [script, "--manifest", "/home/someone/recordings", "--out", "/tmp/x.txt", "--cache", "c", "--seed", "1"]
    assert script_command(argv) == "python studies/scripts/sim_confounds.py --manifest DATA --seed 1"
    bench = os.path.join(harness.ROOT, "benchmarks", "bench_flops.py")
    command = script_command([bench, "--data", "/x/example_data/"])
    assert command == "python benchmarks/bench_flops.py --data EXAMPLE_DATA"


def test_study_output_starts_with_its_header(tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "argv", [os.path.join(harness.ROOT, "studies", "scripts", "s.py"), "--out", "o"])
    path = tmp_path / "out.txt"
    write_output(path, "figures")
    command, commit, machine, body = path.read_text().splitlines()
    assert command == "# command: python studies/scripts/s.py" and body == "figures"
    assert re.fullmatch(r"# commit: .+, \d{4}-\d\d-\d\dT\d\d:\d\dZ", commit)
    assert machine.startswith("# machine: ") and "GFLOP/s (one thread)" in machine
    lines = header(["s.py"], machine={"cpu": "c", "cores": 1, "matmul_gflops": None, "torch": "t", "numpy": "n",
                                      "python": "p", "blas": None}, commit="f00", date="d")
    assert lines.splitlines()[1:] == ["# commit: f00, d",
                                      "# machine: c, 1 cores, torch t, numpy n, Python p, BLAS None"]


# --- config hash ---------------------------------------------------------------------------------


def test_planned_config_hash_is_the_one_the_runs_get(monkeypatch):
    from sklearn.utils import Bunch

    from sklearn_hardness.experiments import _active, run_active_sampling
    from sklearn_hardness.experiments._data import _dataset_spec

    def inputs(dataset, cfg, model, **kw):  # silicone5's labels, no frames and no training
        y = np.repeat(np.arange(5), 40)
        return Bunch(X=np.zeros((len(y), 1)), y=y, target_names=[str(i) for i in range(5)], hardness=None,
                     hardness_unit=None, n_classes=5, model=model, data_id=list(_dataset_spec(dataset, cfg)),
                     object_id=None)

    monkeypatch.setattr(_active, "prepare_inputs", inputs)
    monkeypatch.setattr(_active, "run_tasks", lambda *a, **k: None)
    ran = run_active_sampling("silicone5", quick=True, n_holdout=5, verbose=0).config["config_hash"]
    planned = planned_config_hash("sklearn-hardness reproduce --quick --n-jobs 2 --out o --set n_holdout=5")
    assert planned == ran
    assert planned_config_hash(["sklearn-hardness", "reproduce", "--quick", "--quiet"]) not in (None, ran)
    assert planned_config_hash("sklearn-hardness reproduce --protocol paper") is None
    with pytest.raises(ValueError, match="reproduce"):
        planned_config_hash("sklearn-hardness evaluate everyday")


# --- memory --------------------------------------------------------------------------------------


def test_peak_rss_sees_an_allocation_and_resets():
    import psutil

    reset_peak()
    block = mmap.mmap(-1, 64 * 2**20)  # 64 MiB, touched; unmapped on close whatever the allocator keeps
    block.write(b"\1" * len(block))
    held = psutil.Process().memory_info().rss / 2**20
    assert peak_rss_mb() >= held - 1
    block.close()
    reset_peak()  # the high-water mark falls back to what is resident now
    assert peak_rss_mb() < held - 32
    assert peak_rss_mb(children=True) >= 0


def test_tree_peak_counts_the_children():
    import psutil

    code = "import time, numpy as np; a = np.ones(128 * 2**20 // 8); print('ready', flush=True); time.sleep(1.5)"
    own = psutil.Process().memory_info().rss / 2**20
    with TreePeak(os.getpid(), interval=0.05) as tree:
        child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
        assert child.stdout.readline().strip() == "ready"
        child.wait()
    assert tree.peak_mb > own + 100


def test_stamp_adds_commit_and_machine_below_the_command_line_s_header(tmp_path):
    from sklearn_hardness._cli._header import output_header, read_header

    path = tmp_path / "table.txt"
    path.write_text(output_header("sklearn-hardness reproduce --quick") + "\ntitle\ntable\n")
    machine = {"cpu": "c", "cores": 1, "matmul_gflops": 80.0, "torch": "t", "numpy": "n", "python": "p", "blas": "b"}
    assert stamp(path, machine=machine, commit="f00")
    lines = path.read_text().splitlines()
    assert lines[1:] == ["# commit: f00", "# machine: " + describe(machine), "title", "table"]
    assert read_header(path.read_text())["command"] == "sklearn-hardness reproduce --quick"
    # the harness reads the command line's header as the package writes it
    assert provenance_record(path.read_text()) == read_header(path.read_text())
    assert provenance_record("no header\n") is None
    assert not stamp(path, machine=machine, commit="f00")  # once
    path.write_text("no header\n")
    with pytest.raises(ValueError, match="header line"):
        stamp(path)


def test_notes_go_beside_an_output_and_a_superseded_output_comes_back_from_git(tmp_path):
    from harness.provenance import add_note, restore

    out = tmp_path / "run.txt"
    out.write_text("# command: python s.py\n")
    sidecar = add_note(out, "ran with --cache DIR", date="2026-01-01")
    add_note(out, "a second note", date="2026-01-02")
    assert out.read_text() == "# command: python s.py\n"  # the output itself is never edited
    assert open(sidecar).read().splitlines() == ["# note (2026-01-01): ran with --cache DIR",
                                                 "# note (2026-01-02): a second note"]
    with pytest.raises(ValueError, match="one non-empty line"):
        add_note(out, "two\nlines")
    restored = tmp_path / "readme_at_head.md"
    restore("HEAD:README.md", restored, date="2026-01-03")
    committed = subprocess.run(["git", "-C", harness.ROOT, "show", "HEAD:README.md"], capture_output=True,
                               check=True).stdout
    assert restored.read_bytes() == committed
    assert "restored verbatim from git: git show " in (tmp_path / "readme_at_head.md.provenance").read_text()
    with pytest.raises(FileExistsError, match="new name"):
        restore("HEAD:README.md", restored)


def test_timed_keeps_what_a_command_printed_with_its_time_under_a_header(tmp_path, capsys):
    from harness.figures import missing_header
    from harness.timed import main as timed

    out = tmp_path / "timed.txt"
    timed([str(out), "--as", "python work.py --data DATA", "--", sys.executable, "-c",
           "import time; t = time.process_time(); print('score 0.59')\nwhile time.process_time() - t < 0.3: pass"])
    lines = out.read_text().splitlines()
    assert lines[0] == "# command: python work.py --data DATA" and lines[1].startswith("# commit: ")
    assert lines[3] == "score 0.59"
    cpu = float(re.search(r"CPU ([\d.]+) s", lines[4]).group(1))
    assert lines[4].startswith("wall ") and cpu >= 0.3  # the child's CPU time, not the parent's
    assert missing_header(str(out)) == []
    with pytest.raises(SystemExit, match="failed"):
        timed([str(tmp_path / "no.txt"), "--", sys.executable, "-c", "raise SystemExit(3)"])
    assert not (tmp_path / "no.txt").exists()
