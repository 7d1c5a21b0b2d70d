"""The wheel is the library: no module of the package starts processes, runs git, times matmuls or imports the harness.

Provenance with the commit, the machine's matmul reference and BLAS kernels, config
hashes for pre-registrations and README's table are the development harness's
(``harness/``, outside the wheel); an AST scan over ``sklearn_hardness/`` keeps them there.
"""

import ast
import os
import textwrap

import sklearn_hardness

PACKAGE = os.path.dirname(sklearn_hardness.__file__)

#: Modules whose import means starting processes, sniffing BLAS or the development harness.
_FORBIDDEN_IMPORTS = {"subprocess": "starts processes", "harness": "imports the development harness",
                      "threadpoolctl": "sniffs BLAS kernels (the harness's machine reference)"}
_PROCESS_CALLS = {"system", "popen", "spawnv", "spawnl", "execv", "execl", "posix_spawn", "fork"}
_TIMERS = {"perf_counter", "process_time", "monotonic", "time"}
_MATMULS = {"matmul", "mm", "bmm", "dot", "einsum"}


def _name(func):
    return func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)


def _timed_matmul(function):
    """Whether ``function``'s own body both reads a clock and multiplies matrices."""
    nodes = list(ast.walk(function))
    timed = any(isinstance(n, ast.Call) and _name(n.func) in _TIMERS for n in nodes)
    multiplies = any((isinstance(n, ast.BinOp) and isinstance(n.op, ast.MatMult))
                     or (isinstance(n, ast.Call) and _name(n.func) in _MATMULS) for n in nodes)
    return timed and multiplies


def boundary_violations(source, where="<source>"):
    """What in ``source`` does not belong in the package: ``"where:line: why"`` per finding."""
    found = []
    for node in ast.walk(ast.parse(source)):
        line = f"{where}:{getattr(node, 'lineno', 0)}"
        if isinstance(node, ast.Import):
            roots = [alias.name.split(".")[0] for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            roots = [(node.module or "").split(".")[0]] if node.level == 0 else []
        else:
            roots = []
        found += [f"{line}: {_FORBIDDEN_IMPORTS[r]}" for r in roots if r in _FORBIDDEN_IMPORTS]
        if isinstance(node, ast.Constant) and node.value == "git":
            found.append(f"{line}: runs git")
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and _name(node.func.value) == "os" \
                and node.func.attr in _PROCESS_CALLS:
            found.append(f"{line}: starts processes (os.{node.func.attr})")
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and _timed_matmul(node):
            found.append(f"{line}: times matrix products ({node.name})")
    return found


def test_the_scan_finds_what_the_package_once_did():
    # the provenance module the package had: git through subprocess, a timed matmul, BLAS sniffing
    old = textwrap.dedent('''
        import subprocess, time
        from threadpoolctl import threadpool_info
        def commit():
            return subprocess.run(["git", "rev-parse", "HEAD"]).stdout
        def matmul_gflops(a, b):
            t = time.perf_counter()
            a @ b
            return time.perf_counter() - t
        def rate(a, b):
            start = time.time()
            torch.mm(a, b)
            return time.time() - start
        def version():
            from harness.provenance import git_commit
            return os.popen("uname").read()
        ''')
    found = boundary_violations(old)
    for why in ("starts processes", "sniffs BLAS", "runs git", "times matrix products (matmul_gflops)",
                "times matrix products (rate)", "imports the development harness", "os.popen"):
        assert any(why in f for f in found), why
    assert boundary_violations("import time\ndef fit(a, b):\n    t = time.perf_counter()\n    return a @ b\n") != []
    assert boundary_violations("def f(a, b):\n    return a @ b\n") == []


def test_no_module_of_the_package_starts_processes_times_matmuls_or_imports_the_harness():
    found = []
    for folder, _, files in os.walk(PACKAGE):
        for name in sorted(f for f in files if f.endswith(".py")):
            path = os.path.join(folder, name)
            with open(path) as f:
                found += boundary_violations(f.read(), os.path.relpath(path, PACKAGE))
    assert found == []
