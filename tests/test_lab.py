"""The lab (``benchmarks/``, ``studies/scripts/``, ``harness/``, ``examples/``, ``docs/conf.py``) runs in CI.

Nothing imports the lab's scripts but their readers, so a move in the package breaks
them without a red CI unless a test does. Fast tier: every tracked Python file
compiles; every module of the lab imports without running (scripts do their work
under ``main()``); every ``sklearn_hardness`` name the lab imports resolves; the
lab imports public package names only, but for the short declared list
:data:`PRIVATE_NAMES`. Slow tier: every study script and benchmark runs its smoke
mode (``--smoke``: tiny generated data, seconds), in this process, through its
command line (``main(argv)``).
"""

from __future__ import annotations

import ast
import contextlib
import importlib
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BENCHMARKS = ROOT / "benchmarks"
STUDIES = ROOT / "studies" / "scripts"
HARNESS = ROOT / "harness"

_CONFIG_HASH = ("harness/config_hash.py: the configuration hash of a reproduce command before it runs (for "
                "pre-registrations) is computed only inside the command line and the experiments; no public "
                "function or option gives it")
#: The lab's private package names, each with why no public name serves (the lab reads public names
#: only; the test fails on a private import missing here and on an entry no file imports any more).
PRIVATE_NAMES = {
    "sklearn_hardness._cli.build_parser": _CONFIG_HASH,
    "sklearn_hardness._cli._reproduce._reproduce_config": _CONFIG_HASH,
    "sklearn_hardness.experiments._active._results_hash": _CONFIG_HASH,
    "sklearn_hardness.experiments._config.resolve_convergence_threshold": _CONFIG_HASH,
    "sklearn_hardness.experiments._config.run_config": _CONFIG_HASH,
    "sklearn_hardness.experiments._data._dataset_spec": _CONFIG_HASH,
    "sklearn_hardness.datasets._sim_everyday._profile": "contact_profile_features.py: the ideal reader's rows are "
                                                       "the simulator's own contact profile, which they must follow",
    "sklearn_hardness.datasets._sim_everyday._texture": "contact_profile_features.py: the same, the simulator's "
                                                        "own texture of an object",
    "sklearn_hardness.features._loading_moments.loading_moments": "physiclear_exploration.py: its descriptors read "
                                                                  "the contact at the moments the library's "
                                                                  "geometry and texture features read it",
    "sklearn_hardness.models._stacked.StackedConvLSTMNet": "bench_stacked.py: times the stacked module itself, "
                                                           "which users reach as EnsembleClassifier(stacked=True)",
}


def _tracked_python_files():
    """Every tracked ``.py`` file (every ``.py`` file outside ``.git`` where git cannot list them)."""
    try:
        out = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z", "--", "*.py"], capture_output=True,
                             check=True, timeout=30).stdout.decode()
        files = [ROOT / name for name in out.split("\0") if name]
    except (OSError, subprocess.SubprocessError):
        files = []
    return files or sorted(p for p in ROOT.rglob("*.py") if ".git" not in p.parts)


def _scripts(folder):
    """The runnable scripts of a lab folder (its ``_*.py`` modules are their helpers)."""
    return sorted(p for p in folder.glob("*.py") if not p.name.startswith("_"))


#: Every file of the lab: its names of the package are checked.
LAB_FILES = sorted([*BENCHMARKS.glob("*.py"), *STUDIES.glob("*.py"), *HARNESS.glob("*.py"),
                    *(ROOT / "examples").glob("*.py"), ROOT / "docs" / "conf.py"])
#: The lab's modules that are imported here (the examples run in the slow tier's gallery run, docs/conf.py in the
#: docs build).
LAB_MODULES = sorted([*BENCHMARKS.glob("*.py"), *STUDIES.glob("*.py"), *HARNESS.glob("*.py")])
#: What the slow tier smoke-runs.
SCRIPTS = _scripts(BENCHMARKS) + _scripts(STUDIES)


def _rel(path):
    return path.relative_to(ROOT).as_posix()


def test_the_lab_is_where_this_test_looks():
    assert len(SCRIPTS) >= 30 and (BENCHMARKS / "run.py") in SCRIPTS and (HARNESS / "provenance.py") in LAB_MODULES
    assert all(p.is_file() for p in LAB_FILES)


def test_every_tracked_python_file_compiles():
    failures = []
    files = _tracked_python_files()
    for path in files:
        try:
            compile(path.read_bytes(), str(path), "exec", dont_inherit=True)
        except (SyntaxError, ValueError) as exc:  # merge markers, stray text, bad indentation
            failures.append(f"{_rel(path)}:{getattr(exc, 'lineno', '?')}: {exc}")
    assert len(files) > 100
    assert not failures, "\n".join(failures)


# --- importing the lab's modules ---------------------------------------------------------------------------


@contextlib.contextmanager
def script_folder(folder):
    """Import the modules of ``folder`` as its scripts see each other: the folder first on ``sys.path``.

    On the way out ``sys.path`` is restored and the modules loaded from the
    repository outside its packages are forgotten: ``benchmarks/_harness.py``
    and ``studies/scripts/_harness.py`` share a name.
    """
    path, modules = list(sys.path), set(sys.modules)
    sys.path.insert(0, str(folder))
    try:
        yield
    finally:
        sys.path[:] = path
        for name in set(sys.modules) - modules:
            file = getattr(sys.modules[name], "__file__", None) or ""
            if "." not in name and Path(file).resolve().is_relative_to(ROOT) \
                    and name not in ("harness", "sklearn_hardness", "tests"):
                del sys.modules[name]


def import_lab_module(path):
    """The module of ``path`` (a harness module as ``harness.<name>``), imported without running its script."""
    if path.parent == HARNESS:
        return importlib.import_module("harness" if path.stem == "__init__" else f"harness.{path.stem}")
    return importlib.import_module(path.stem)


@pytest.mark.parametrize("path", LAB_MODULES, ids=_rel)
def test_lab_module_imports_without_running(path, capsys):
    with script_folder(path.parent):
        module = import_lab_module(path)
    assert Path(module.__file__).resolve() == path
    out = capsys.readouterr()
    assert not out.out, f"importing {_rel(path)} printed: its work must wait for main() (__name__ == '__main__')"
    if path in SCRIPTS:
        assert callable(getattr(module, "main", None)), f"{_rel(path)} has no main(argv) to run it by"


# --- the package's names the lab reads ---------------------------------------------------------------------

#: A string that is a dotted name of the package as a whole: a module run by ``python -m``.
_MODULE_STRING = re.compile(r"sklearn_hardness(\.\w+)+")


def _private(dotted):
    return any(p.startswith("_") and not p.endswith("__") for p in dotted.split(".")[1:])


def package_names(source, where="<source>"):
    """``(line, module, name or None)`` of every name of the package that ``source`` imports or runs.

    Imports at any depth (inside functions too); a string that is exactly a
    module's dotted name (``python -m sklearn_hardness.x``) is a module too.
    """
    out = []
    for node in ast.walk(ast.parse(source, where)):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name, None) for a in node.names if a.name.split(".")[0] == "sklearn_hardness"]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module \
                and node.module.split(".")[0] == "sklearn_hardness":
            out += [(node.lineno, node.module, a.name) for a in node.names]
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and _MODULE_STRING.fullmatch(node.value):
            out.append((node.lineno, node.value, None))
    return out


def unresolved(module, name):
    """Why ``module`` (and ``name`` in it) cannot be imported from the installed package, or None."""
    try:
        mod = importlib.import_module(module)
    except Exception as exc:  # noqa: BLE001 - reported with the file and line that import it
        return f"module {module} does not import ({type(exc).__name__}: {exc})"
    if name is None or name == "*" or hasattr(mod, name):
        return None
    if importlib.util.find_spec(f"{module}.{name}") is None:
        return f"{module} has no name {name}"
    return None


def test_the_name_scan_sees_every_kind_of_reference():
    source = ("import sklearn_hardness.io\nfrom sklearn_hardness.datasets import make_presses as mp\n"
              "def f():\n    from sklearn_hardness.models._x import y\n"
              "cmd = ['python', '-m', 'sklearn_hardness._cli']\ndoc = 'see sklearn_hardness.io and more'\n")
    assert sorted(package_names(source)) == [(1, "sklearn_hardness.io", None),
                                             (2, "sklearn_hardness.datasets", "make_presses"),
                                             (4, "sklearn_hardness.models._x", "y"),
                                             (5, "sklearn_hardness._cli", None)]
    assert unresolved("sklearn_hardness.datasets", "make_presses") is None
    assert unresolved("sklearn_hardness.datasets", "nothing") == "sklearn_hardness.datasets has no name nothing"
    assert unresolved("sklearn_hardness.no_such_module", None).startswith("module sklearn_hardness.no_such_module")
    assert [_private(n) for n in ("sklearn_hardness.io", "sklearn_hardness._cli", "sklearn_hardness.a._b.c",
                                  "sklearn_hardness.__version__")] == [False, True, True, False]


@pytest.mark.parametrize("path", LAB_FILES, ids=_rel)
def test_every_package_name_the_lab_reads_resolves(path):
    missing = []
    for line, module, name in package_names(path.read_text(encoding="utf-8"), str(path)):
        why = unresolved(module, name)
        if why:
            missing.append(f"{_rel(path)}:{line}: {why}")
    assert not missing, "\n".join(missing)


def test_the_lab_reads_public_package_names_but_the_declared_ones():
    found = {}
    for path in LAB_FILES:
        for line, module, name in package_names(path.read_text(encoding="utf-8"), str(path)):
            dotted = module if name is None else f"{module}.{name}"
            if _private(dotted):
                found.setdefault(dotted, []).append(f"{_rel(path)}:{line}")
    undeclared = [f"{where}: {dotted}" for dotted, places in sorted(found.items()) if dotted not in PRIVATE_NAMES
                  for where in places]
    assert not undeclared, ("private package names the lab imports: use the public API, move the helper into the "
                            "lab, or declare it in PRIVATE_NAMES with why:\n" + "\n".join(undeclared))
    stale = sorted(set(PRIVATE_NAMES) - set(found))
    assert not stale, f"PRIVATE_NAMES entries no file of the lab imports any more (delete them): {stale}"
    assert all(isinstance(why, str) and why for why in PRIVATE_NAMES.values())


# --- smoke runs of every study script and benchmark --------------------------------------------------------

#: Every study script's and benchmark's smoke run: its arguments beside ``--smoke``, one list per run.
#: ``{PHYSICLEAR}``, ``{GRASPS}``, ``{MANIFEST}``: tiny copies of the real sets' layouts (harness/smoke.py);
#: ``{OUT}``: a path in a fresh folder. ``--out`` is given to a few: a study's output header measures the machine.
SMOKE = {
    "benchmarks/bench_active_sampling.py": [[], ["--paired-seeds", "2"]],
    "benchmarks/bench_convlstm.py": [[]],
    "benchmarks/bench_cross_val.py": [[]],
    "benchmarks/bench_device.py": [["--out", "{OUT}"]],
    "benchmarks/bench_features.py": [[]],
    "benchmarks/bench_fit_predict.py": [[], ["--data", "{PHYSICLEAR}"]],
    "benchmarks/bench_flops.py": [[]],
    "benchmarks/bench_mc_dropout.py": [[], ["--pipelines"]],
    "benchmarks/bench_paired_sharing.py": [["shared"], ["separate"]],
    "benchmarks/bench_simulator.py": [[], ["--preset", "everyday"]],
    "benchmarks/bench_stacked.py": [[]],
    "benchmarks/bench_time_error.py": [["--out", "{OUT}"]],
    "benchmarks/run.py": [["flops", "--log", "{OUT}"]],
    "studies/scripts/anchor_split.py": [["--data", "{PHYSICLEAR}"]],
    "studies/scripts/augmentation.py": [["--data", "{GRASPS}", "--roi"]],
    "studies/scripts/blas_kernels.py": [[]],
    "studies/scripts/contact_profile_features.py": [["--heads", "--net-inputs"]],
    "studies/scripts/contact_selection.py": [[]],
    "studies/scripts/convergence.py": [[]],
    "studies/scripts/loading_compliance.py": [[]],
    "studies/scripts/margin_interval.py": [[]],
    "studies/scripts/mc_share.py": [[]],
    "studies/scripts/model_baselines.py": [[]],
    "studies/scripts/nested_selection.py": [["--data", "{PHYSICLEAR}"]],
    "studies/scripts/physiclear_exploration.py": [["--data", "{PHYSICLEAR}", "--cnn"]],
    "studies/scripts/pipeline_inputs.py": [[]],
    "studies/scripts/power_thompson.py": [[]],
    "studies/scripts/real_contact_geometry.py": [["--data", "{PHYSICLEAR}"]],
    "studies/scripts/real_net_augmentation.py": [["--data", "{PHYSICLEAR}"]],
    "studies/scripts/recommendation.py": [[]],
    "studies/scripts/sim_confounds.py": [[]],
    "studies/scripts/sim_pretraining.py": [["--data", "{GRASPS}"]],
    "studies/scripts/sim_to_real.py": [["--data", "{GRASPS}", "--feature-subsets", "--each-seed", "--out", "{OUT}"]],
    "studies/scripts/sim_vs_real_stats.py": [["--data", "{GRASPS}", "--by-kind", "--features",
                                              "--manifest", "{MANIFEST}"]],
    "studies/scripts/training_objects.py": [["--data", "{GRASPS}", "--roi"]],
    "studies/scripts/wedge_force.py": [["--data", "{GRASPS}"]],
}
SMOKE_RUNS = [(script, argv) for script, runs in SMOKE.items() for argv in runs]


def test_every_study_script_and_benchmark_has_a_smoke_entry():
    assert sorted(SMOKE) == [_rel(p) for p in SCRIPTS], "add the new script's smoke run to SMOKE (and --smoke to it)"
    for path in SCRIPTS:  # its command line takes --smoke: harness.smoke's, or its own
        tree = ast.parse(path.read_text(encoding="utf-8"))
        takes = any(isinstance(n, ast.Constant) and n.value == "--smoke"
                    or isinstance(n, ast.ImportFrom) and n.module == "harness.smoke" for n in ast.walk(tree))
        assert takes, f"{_rel(path)} has no --smoke"


@pytest.fixture(scope="module")
def smoke_data(tmp_path_factory):
    """``{name: path}`` of the tiny layouts, each written when a run first asks for it."""
    from harness import smoke

    writers = {"PHYSICLEAR": smoke.write_development_layout, "GRASPS": smoke.write_estimate_modulus_layout,
               "MANIFEST": smoke.write_presses_manifest}
    made = {}

    def path(name):
        if name not in made:
            made[name] = str(writers[name](tmp_path_factory.mktemp("smoke") / name.lower()))
        return made[name]

    return path


def _repository_state():
    """The working tree's changed, untracked and ignored files, Python's and pytest's caches aside (None without
    git)."""
    try:
        out = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=all", "--ignored"],
                             capture_output=True, text=True, check=True, timeout=60).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    return sorted(line for line in out.splitlines() if "__pycache__/" not in line and ".pytest_cache/" not in line)


@pytest.mark.slow
@pytest.mark.torch_threads(1)  # tiny nets are fastest on one thread
@pytest.mark.parametrize("script, argv", SMOKE_RUNS, ids=[" ".join([s, *a]) for s, a in SMOKE_RUNS])
def test_smoke_run(script, argv, smoke_data, tmp_path, monkeypatch, capsys):
    path, out = ROOT / script, tmp_path / "out" / "output"
    out.parent.mkdir()
    args = ["--smoke"] + [str(out) if a == "{OUT}" else smoke_data(a[1:-1]) if a[:1] == "{" else a for a in argv]
    before = _repository_state()
    monkeypatch.chdir(tmp_path)  # what a script writes into its working folder lands here
    monkeypatch.setattr(sys, "argv", [str(path), *args])  # as its command line gives them (the output header)
    with script_folder(path.parent):
        status = import_lab_module(path).main(args)  # its command line, in this process
    assert not isinstance(status, int) or status == 0, f"{script} exited with {status}"  # main() may return a result
    assert capsys.readouterr().out.strip(), f"{script} printed nothing"
    if "{OUT}" in argv:
        written = sorted(out.parent.iterdir())
        assert written and all(p.stat().st_size for p in written), f"{script} wrote nothing to {out}*"
        if script.startswith("studies/"):  # a study's output names the command that made it
            assert (out.parent / "output").read_text().startswith(f"# command: python {script} --smoke")
    assert _repository_state() == before, f"{script} --smoke wrote into the repository"
