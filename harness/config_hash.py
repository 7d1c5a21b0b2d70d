"""The configuration hash a ``sklearn-hardness reproduce`` command keys its runs by, before it runs.

A pre-registration names its command; the hash says which records of a
``results.jsonl`` that command will make or resume (each record's
``key["config"]``, also in the ``config_hash`` of ``table.txt``'s header).

    python -m harness.config_hash "sklearn-hardness reproduce --quick --n-jobs 2"

It reads the package's private configuration code, as ``run_active_sampling``
computes the hash; ``tests/test_harness.py`` checks the two agree.
"""

from __future__ import annotations

import argparse
import shlex

import numpy as np

__all__ = ["planned_config_hash"]


def planned_config_hash(command):
    """The configuration hash of a ``sklearn-hardness reproduce`` command, without running it.

    Parameters
    ----------
    command : str or list of str
        The command line (``"sklearn-hardness reproduce ..."``) or its words.

    Returns
    -------
    config_hash : str or None
        The hash in the records' ``key["config"]``; None for ``--protocol
        paper`` (its runs have one hash per experiment).

    Examples
    --------
    >>> from harness.config_hash import planned_config_hash
    >>> len(planned_config_hash("sklearn-hardness reproduce --quick"))
    12
    """
    from sklearn_hardness._cli import build_parser
    from sklearn_hardness._cli._reproduce import _reproduce_config
    from sklearn_hardness.experiments import load_dataset
    from sklearn_hardness.experiments._active import _results_hash
    from sklearn_hardness.experiments._config import resolve_convergence_threshold, run_config
    from sklearn_hardness.experiments._data import _dataset_spec

    words = shlex.split(command) if isinstance(command, str) else list(command)
    if words[:2] != ["sklearn-hardness", "reproduce"]:
        raise ValueError(f"expected a 'sklearn-hardness reproduce ...' command, got {command!r}.")
    args = build_parser().parse_args(words[1:])
    if args.protocol != "active":
        return None
    config = _reproduce_config(args)
    dataset = args.dataset or args.preset
    cfg, _ = run_config(dataset, args.preset, args.model, args.n_runs, args.quick, config)
    spec = _dataset_spec(dataset, cfg)
    if spec is None:
        raise ValueError("the dataset must be a simulator preset or a manifest CSV path to hash it before a run.")
    data = load_dataset(dataset, cfg)  # lazy videos: labels and object ids only
    y = np.asarray(data["target"])
    object_id = data.get("object_id")
    object_id = None if object_id is None else np.asarray(object_id)
    n_classes = max(len(data.get("target_names", ())), int(y.max()) + 1)  # as prepare_inputs counts them
    resolve_convergence_threshold(cfg, n_classes)
    return _results_hash(cfg, list(spec), object_id, y)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("command", help="the command line, quoted: \"sklearn-hardness reproduce ...\"")
    print(planned_config_hash(ap.parse_args(argv).command))


if __name__ == "__main__":
    main()
