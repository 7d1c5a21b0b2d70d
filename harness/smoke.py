"""Smoke runs of the lab: every study script and benchmark on tiny generated data, in seconds.

``python studies/scripts/NAME.py --smoke`` (likewise ``benchmarks/bench_NAME.py
--smoke``) runs the script's own code end to end on a few simulated presses
with tiny settings (one or two epochs, one seed, small frames), writing nothing
into the repository. Arguments given beside ``--smoke`` still win over its
settings. CI runs every script's smoke run (``tests/test_lab.py``, slow tier),
so that a change in the package that breaks a script fails CI, not its next
reader. The figures of a smoke run mean nothing.

Scripts that read a real set take a tiny copy of its layout as ``--data``:

    python -m harness.smoke physiclear FOLDER        # PhysiCLeAR: dataset/*.mov, utils/constants.py
    python -m harness.smoke estimate_modulus FOLDER  # EstimateModulus' example_data: *.avi and their .pkl
    python -m harness.smoke manifest FOLDER          # recordings listed in a manifest.csv (load_press_videos)
"""

from __future__ import annotations

import argparse
import pickle
from pathlib import Path

import numpy as np

from . import ROOT

__all__ = ["SMOKE_HELP", "TINY_PRESSES", "TINY_ACTIVE", "add_smoke_argument", "parse_args", "tiny_presses",
           "write_physiclear_layout", "write_development_layout", "write_estimate_modulus_layout",
           "write_presses_manifest"]

SMOKE_HELP = ("tiny generated data and settings, a few seconds, nothing written into the repository: what CI runs "
              "(harness/smoke.py); options given beside it still win")

#: ``make_presses`` arguments of a tiny set of each preset: few presses, small frames, short videos,
#: no codec (the codec's round trip is the slow part of the everyday preset); ``everyday``: five objects
#: of each rank, as many as evaluate's five object-disjoint folds need.
TINY_PRESSES = {
    "silicone5": dict(n_per_class=5, image_size=(48, 64)),
    "shore9": dict(n_per_class=3, image_size=(48, 64)),
    "everyday": dict(n_objects=15, class_ratio=(1.0, 1.0, 1.0), n_per_class=2, image_size=(48, 64), codec=None,
                     video_length=40),
}

#: Configuration overrides of a tiny active-sampling run (``run_active_sampling(..., **TINY_ACTIVE)``): one press
#: each to start, to query and to test, one query, one epoch, two MC passes, and no convergence rule (a net
#: trained one epoch never meets it, and every run goes on to its query).
TINY_ACTIVE = dict(n_initial=1, n_per_query=1, n_iterations=1, n_test=1, initial_epochs=1, epochs_per_query=1,
                   n_samples=2, convergence_threshold=None)

#: The objects of the tiny EstimateModulus layout: the two families of ``studies/scripts/_estimate_modulus.py``
#: (hardest first) and one object outside them, as the real folder holds.
GRASP_OBJECTS = ("golf_ball", "purple_ball_hardest", "green_ball_softer", "orange_ball_softest",
                 "blue_foam_brick_harder", "red_foam_brick_softer", "yellow_foam_brick_softest", "tennis_ball")

#: The development objects of the public PhysiCLeAR set, one a line (``#`` comments).
DEVELOPMENT_OBJECTS = Path(ROOT) / "studies" / "real_development_objects.txt"


def add_smoke_argument(parser):
    """Add ``--smoke`` to a script's parser."""
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    return parser


def parse_args(parser, argv=None, **smoke):
    """``parser.parse_args(argv)``; with ``--smoke``, ``smoke`` replaces the parser's defaults first.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The script's parser, with ``--smoke`` (:func:`add_smoke_argument`).
    argv : list of str or None, default=None
        The arguments (None: ``sys.argv[1:]``).
    **smoke
        Defaults of the smoke run, by destination (``n_jobs=1``): arguments
        given explicitly still win.

    Returns
    -------
    args : argparse.Namespace

    Examples
    --------
    >>> import argparse
    >>> from harness.smoke import add_smoke_argument, parse_args
    >>> ap = add_smoke_argument(argparse.ArgumentParser())
    >>> _ = ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    >>> _ = ap.add_argument("--n-jobs", type=int, default=2)
    >>> args = parse_args(ap, ["--smoke", "--n-jobs", "3"], seeds=[0], n_jobs=1)
    >>> args.smoke, args.seeds, args.n_jobs
    (True, [0], 3)
    >>> parse_args(ap, [], seeds=[0]).seeds
    [0, 1, 2]
    """
    args = parser.parse_args(argv)
    if not getattr(args, "smoke", False) or not smoke:
        return args
    unknown = sorted(set(smoke) - set(vars(args)))
    if unknown:
        raise ValueError(f"smoke defaults for arguments the parser does not have: {unknown}")
    saved = {dest: parser.get_default(dest) for dest in smoke}
    parser.set_defaults(**smoke)
    try:
        return parser.parse_args(argv)
    finally:
        parser.set_defaults(**saved)


def tiny_presses(preset, smoke=True):
    """The ``make_presses`` arguments of a tiny set of ``preset`` (``{}`` unless ``smoke``)."""
    return dict(TINY_PRESSES[preset]) if smoke else {}


def write_physiclear_layout(root, constants, videos):
    """Write a copy of PhysiCLeAR's layout: ``utils/constants.py`` and ``dataset/<object>_<i>.mov``.

    Parameters
    ----------
    root : path-like
        The folder to write (created).
    constants : str
        The text of ``utils/constants.py``.
    videos : dict of str to list of ndarray
        Per object (without the ``physiclear_`` prefix), its presses:
        ``(T, H, W, 3)`` ``uint8`` videos.

    Returns
    -------
    root : Path
    """
    from sklearn_hardness.io import write_video

    root = Path(root)
    (root / "utils").mkdir(parents=True)
    (root / "utils" / "constants.py").write_text(constants)
    (root / "dataset").mkdir()
    for obj, presses in videos.items():
        for i, video in enumerate(presses):
            write_video(root / "dataset" / f"{obj}_{i}.mov", video)
    return root


def development_objects():
    """The development objects of ``studies/real_development_objects.txt``, in its order."""
    lines = (line.split("#", 1)[0].strip() for line in DEVELOPMENT_OBJECTS.read_text().splitlines())
    return [name for name in lines if name]


def write_development_layout(root, n_per_object=1, random_state=0):
    """A tiny PhysiCLeAR copy holding the development objects: simulated presses, the set's constants.py layout.

    Each development object gets the presses of one object of a tiny simulated
    ``everyday`` set, drawn in a seeded random order, and its rank (soft 0,
    moderate 1, hard 2). Every 7th
    object is a test object and every 9th a validation object of the set's own
    split; objects that share their first word are parts of one object
    (``OBJECTS_PARTS``), as a toothbrush's handle and bristles are.
    """
    from sklearn_hardness.datasets import make_presses

    names = development_objects()
    # the set's videos are whole recordings (none short or truncated), large enough for the coarsest band of
    # physiclear_exploration.py's radial spectrum
    sim = make_presses("everyday", **dict(tiny_presses("everyday"), n_objects=len(names), n_per_class=n_per_object,
                                          image_size=(72, 96), short_fraction=0.0, truncated_fraction=0.0),
                       shuffle=False, random_state=random_state)
    rank_of = {"soft": 0, "moderate": 1, "hard": 2}
    ids = np.random.default_rng(random_state).permutation(list(dict.fromkeys(sim.object_id.tolist())))
    videos, ranks = {}, {}
    for name, obj in zip(names, ids):
        index = np.flatnonzero(sim.object_id == obj)
        videos[name] = [sim.videos[i] for i in index]
        ranks[f"physiclear_{name}"] = rank_of[str(sim.target_names[sim.target[index[0]]])]
    split = {"TEST_OBJECTS": names[6::7], "VAL_OBJECTS": [n for n in names[8::9] if n not in names[6::7]]}
    split["TRAIN_OBJECTS"] = [n for n in names if n not in split["TEST_OBJECTS"] + split["VAL_OBJECTS"]]
    wholes = {}
    for name in names:
        wholes.setdefault(name.split("_")[0], []).append(name)
    parts = {f"a {whole}": {part: f"physiclear_{part}" for part in members}
             for whole, members in wholes.items() if len(members) > 1}
    constants = "".join(f"{key} = {[f'physiclear_{n}' for n in value]!r}\n" for key, value in split.items())
    constants += (f"HARDNESS_RANK = {ranks!r}\nHARDNESS_MAP = {{0: 'soft', 1: 'moderately hard', 2: 'hard'}}\n"
                  f"OBJECTS_PARTS = {parts!r}\n")
    return write_physiclear_layout(root, constants, videos)


def write_estimate_modulus_layout(root, n_per_object=2, random_state=0):
    """A tiny copy of EstimateModulus' ``example_data``: grasp videos with their force and width per frame.

    Each object of :data:`GRASP_OBJECTS` gets ``n_per_object`` simulated
    presses (``<object>_<i>.avi``, the last one named ``<object>__t=0.avi``
    as the later recordings are), each with ``<video>_forces.pkl`` (N) and
    ``<video>_widths.pkl`` (m, closing as the press goes in): pickled NumPy
    arrays, as the real folder holds them.
    """
    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.io import write_video

    root = Path(root)
    root.mkdir(parents=True)
    sim = make_presses("everyday", **dict(tiny_presses("everyday"), n_objects=len(GRASP_OBJECTS),
                                          n_per_class=n_per_object, video_length=30),
                       shuffle=False, random_state=random_state)
    k = 0
    for obj in GRASP_OBJECTS:
        for i in range(n_per_object):
            stem = f"{obj}__t=0" if i == n_per_object - 1 and i else f"{obj}_{i + 1}"
            write_video(root / f"{stem}.avi", sim.videos[k], fps=30.0, fourcc="MJPG")
            force = np.asarray(sim.force[k], dtype=float)
            width = 0.05 - np.maximum(np.asarray(sim.position[k], dtype=float), 0.0) / 1000.0
            for kind, values in (("forces", force), ("widths", width)):
                with open(root / f"{stem}_{kind}.pkl", "wb") as f:
                    pickle.dump(values, f)
            k += 1
    return root


def write_presses_manifest(folder, random_state=0):
    """Write a tiny simulated ``everyday`` set as recordings: videos, force and position files, ``manifest.csv``.

    The columns ``sklearn_hardness.datasets.load_press_videos`` reads: ``path``,
    ``label``, ``hardness``, ``object_id``, ``force_path``, ``position_path``.
    Returns the manifest's path.
    """
    import csv

    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.io import write_video

    folder = Path(folder)
    folder.mkdir(parents=True)
    sim = make_presses("everyday", **tiny_presses("everyday"), random_state=random_state)
    manifest = folder / "manifest.csv"
    with open(manifest, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["path", "label", "hardness", "object_id", "force_path", "position_path"])
        for i in range(len(sim.target)):
            name = f"press_{i:03d}"
            write_video(folder / f"{name}.avi", sim.videos[i], fps=sim.fps)
            np.save(folder / f"{name}_force.npy", np.asarray(sim.force[i]))
            np.save(folder / f"{name}_position.npy", np.asarray(sim.position[i]))
            writer.writerow([f"{name}.avi", sim.target_names[sim.target[i]], sim.hardness[sim.target[i]],
                             sim.object_id[i], f"{name}_force.npy", f"{name}_position.npy"])
    return manifest


def main(argv=None):
    ap = argparse.ArgumentParser(description="Write a tiny copy of a real set's layout, for the scripts' --smoke.")
    ap.add_argument("layout", choices=["physiclear", "estimate_modulus", "manifest"])
    ap.add_argument("folder", help="where to write it (must not exist)")
    args = ap.parse_args(argv)
    write = {"physiclear": write_development_layout, "estimate_modulus": write_estimate_modulus_layout,
             "manifest": write_presses_manifest}[args.layout]
    print(write(args.folder))


if __name__ == "__main__":
    main()
