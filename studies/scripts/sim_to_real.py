"""Study: pipelines trained only on simulated presses, ordering real objects by softness.

Trains the ready-made pipelines of ``evaluate`` (``peak_change``,
``contact_profile``, ``contact_profile_3``, ``contact_profile_nn``, ``convlstm_intensity``, ``ofnn_quantiles``) on
``make_presses("everyday")``
and predicts every real GelSight Wedge grasp of ``GelSight-lab/EstimateModulus``
(``--data``: its ``example_data`` folder, kept locally, never committed; see
``studies/scripts/_estimate_modulus.py``). Each video's expected hardness rank is
``sum_c predict_proba_c * rank_c`` (soft 1, moderate 2, hard 3); an object's
is the mean over its videos. Reported per object family (balls: golf ball >
purple > green > orange; foam bricks: blue > red > yellow, 9 within-family
pairs): the pairs ordered right (the harder object's expected rank strictly
higher), the expected rank of every object, and the contact status of every
video under the default ``ContactFrameSelector``.

    python studies/scripts/sim_to_real.py --data EXAMPLE_DATA
        [--pipelines peak_change contact_profile contact_profile_3 contact_profile_nn] [--roi] [--seed 0]
        [--sim-seeds 0] [--each-seed] [--cache DIR] [--variant NAME] [--param NAME=VALUE ...]
        [--feature-subsets] [--out FILE] [--smoke]

The simulated videos are kept every 2nd pixel (120x160) in memory, the real
ones cropped (``--roi``: to the gel, ``GEL_ROI``) and kept every 2nd pixel
(240x320 for the full frame, like a GelSight Mini): both give the contact
curve and ``ContactProfileFeatures`` the same pixel grid as full resolution.
``--cache DIR`` stores the rendered simulated set there (``.npz``) for reruns;
``--variant`` starts from a named variant of the preset (``_sim_variants.py``);
``--param`` overrides an ``everyday`` parameter (as in ``sim_vs_real_stats``);
``--feature-subsets`` adds which ``ContactProfileFeatures`` carry over, alone and
combined (balanced logistic regression on subsets, beside their object-disjoint
score on the preset). ``--each-seed`` trains on each of ``--sim-seeds`` alone
instead of on their pooled presses and ends with the pairs ordered right per
training seed (with ``--feature-subsets``, per subset too): one simulated set is
one draw of objects, and the order of the real objects can move with it.
``--out FILE`` also writes the printed text there after a provenance line
(``studies/outputs``).
Time and peak memory are printed beside the figures.
"""

import argparse
import time
from collections import Counter
from pathlib import Path

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _estimate_modulus import FAMILIES, GEL_ROI, expected_rank, family_pairs, load_estimate_modulus
from _sim_variants import VARIANTS, variant_params
from sim_vs_real_stats import parse_param

from harness.memory import peak_rss_mb, reset_peak
from harness.provenance import write_output
from harness.smoke import add_smoke_argument, parse_args, tiny_presses


def simulated(seed, stride=2, cache=None, **params):
    """``make_presses("everyday")`` rendered once: (list of videos, target, hardness, names, object_id)."""
    from sklearn_hardness.datasets import make_presses

    tag = "_".join(f"{k}={v}" for k, v in sorted(params.items())).replace(" ", "")
    path = None if cache is None else Path(cache) / f"everyday_seed{seed}_stride{stride}{tag}.npz"
    data = make_presses("everyday", random_state=seed, **params)  # lazy: rendered on access
    if path is not None and path.exists():
        z = np.load(path)
        videos = np.split(z["frames"], np.cumsum(z["lengths"])[:-1])
        return videos, z["target"], z["hardness"], z["target_names"], np.asarray(data.object_id)
    videos = [np.ascontiguousarray(data.videos[i][:, ::stride, ::stride]) for i in range(len(data.videos))]
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(path, frames=np.concatenate(videos), lengths=[len(v) for v in videos],
                 target=data.target, hardness=data.hardness, target_names=data.target_names)
    return (videos, np.asarray(data.target), np.asarray(data.hardness), np.asarray(data.target_names),
            np.asarray(data.object_id))


def named_pipeline(name, seed):
    """The pipeline ``evaluate`` runs under ``name`` (:func:`~sklearn_hardness.models.make_named_pipeline`)."""
    from sklearn_hardness.models import make_named_pipeline

    return make_named_pipeline(name, random_state=seed)


def order_report(name, est, real, hardness):
    """Fit-free part: expected ranks of the real videos and the family pairs ordered right."""
    proba = np.asarray(est.predict_proba(real.videos))
    scores = expected_rank(proba, est.classes_, hardness)
    return scores, family_pairs(real.object_name, scores)


#: Feature subsets of ``--feature-subsets`` (ContactProfileFeatures names); None: all of them (twelve
#: since issue 20 added ``log_loading_time`` and ``log_contact_spread``); names with a leading ``-``: all
#: but those (the second row: the ten features of before issue 20).
SUBSETS = [None, "-log_loading_time -log_contact_spread", "-concentration", "log_peak_change",
           "peak_over_precontact", "rise_frames", "area_at_peak", "concentration", "rise_frames area_at_peak",
           "peak_over_precontact rise_frames area_at_peak", "log_loading_time", "log_contact_spread",
           "log_peak_change log_loading_time log_contact_spread"]


def feature_subsets(videos, target, groups, real, rl, hardness, say=print):
    """ContactProfileFeatures + balanced logistic regression on subsets of the features.

    Per subset: the within-family pairs of the real grasps ordered right when
    trained on all simulated presses, and the object-disjoint 5-fold balanced
    accuracy on the simulated presses (features computed once). ``rl``: the
    real grasps' features (``ContactProfileFeatures().fit_transform``, the
    same for every training set). Returns ``{subset label: (pairs right,
    balanced accuracy)}``.
    """
    from sklearn.linear_model import LogisticRegression
    from sklearn.metrics import balanced_accuracy_score
    from sklearn.model_selection import StratifiedGroupKFold, cross_val_predict
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    from sklearn_hardness.features import ContactProfileFeatures

    cp = ContactProfileFeatures().fit(videos)
    sim = cp.transform(videos)
    names = list(cp.get_feature_names_out())
    say("\n| ContactProfileFeatures used | pairs right | everyday object-disjoint bal. acc. |\n|---|---|---|")
    result = {}
    for subset in SUBSETS:
        if subset is None:
            cols = list(range(len(names)))
        elif subset.startswith("-"):
            dropped = [n[1:] for n in subset.split()]
            assert set(dropped) <= set(names), f"unknown features in {subset!r}"
            cols = [j for j, n in enumerate(names) if n not in dropped]
        else:
            cols = [names.index(n) for n in subset.split()]
        est = make_pipeline(StandardScaler(), LogisticRegression(class_weight="balanced", max_iter=2000))
        pred = cross_val_predict(est, sim[:, cols], target, groups=groups,
                                 cv=StratifiedGroupKFold(5, shuffle=True, random_state=0))
        est.fit(sim[:, cols], target)
        fams = family_pairs(real.object_name, expected_rank(est.predict_proba(rl[:, cols]), est.classes_,
                                                            hardness))
        right, total = sum(r for r, _, _ in fams.values()), sum(n for _, n, _ in fams.values())
        result[subset or "all"] = (right, balanced_accuracy_score(target, pred))
        say(f"| {subset or 'all'} | {right}/{total} | {result[subset or 'all'][1]:.2f} |")
    return result


def seed_row(label, rights, total, last):
    """A row of the ``--each-seed`` tables: pairs ordered right per simulated set, their mean, and ``last``."""
    return f"| {label} | " + " | ".join(f"{r}/{total}" for r in rights) + f" | {np.mean(rights):.1f} | {last} |"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="EstimateModulus example_data folder")
    parser.add_argument("--pipelines", nargs="+",
                        default=["peak_change", "contact_profile", "contact_profile_3", "contact_profile_nn"],
                        help="evaluate's names (convlstm_intensity and ofnn_quantiles too)")
    parser.add_argument("--roi", action="store_true", help="crop the real grasps to the gel")
    parser.add_argument("--seed", type=int, default=0, help="seed of the nets")
    parser.add_argument("--sim-seeds", type=int, nargs="+", default=[0],
                        help="simulated training sets (their presses are pooled)")
    parser.add_argument("--each-seed", action="store_true",
                        help="train on each of --sim-seeds alone (not pooled); end with the pairs right per seed")
    parser.add_argument("--cache", default=None, help="folder to keep the rendered simulated set in")
    parser.add_argument("--out", default=None, help="also write the printed text there, after a provenance line")
    parser.add_argument("--feature-subsets", action="store_true",
                        help="also: which ContactProfileFeatures carry over, alone and combined")
    parser.add_argument("--variant", default=None, choices=list(VARIANTS), help="a named variant (_sim_variants.py)")
    parser.add_argument("--param", action="append", default=[], type=parse_param,
                        help="override an everyday parameter, NAME=VALUE or NAME=LO,HI")
    add_smoke_argument(parser)
    args = parse_args(parser, argv)
    params = dict(tiny_presses("everyday", args.smoke), **variant_params(args.variant, args.param))

    from sklearn_hardness.preprocessing import ContactFrameSelector

    out = []

    def say(text=""):
        print(text, flush=True)
        out.append(text)

    t0 = time.perf_counter()
    real = load_estimate_modulus(args.data, roi=GEL_ROI if args.roi else None, stride=2)
    sel = ContactFrameSelector().fit([real.videos[i] for i in range(len(real.videos))])
    status = Counter(sel.selection_.status.tolist())
    say(f"real grasps: {len(real.videos)} videos of {len(set(real.object_name))} objects, "
        f"{'gel ROI ' + str(GEL_ROI) if args.roi else 'full frame'}; contact status: {dict(status)}")
    for obj in dict.fromkeys(real.object_name.tolist()):
        st = sel.selection_.status[real.object_name == obj]
        if (st != "contact").any():
            say(f"  {obj}: {', '.join(st.tolist())}")

    trainings = [[s] for s in args.sim_seeds] if args.each_seed else [args.sim_seeds]
    members = [m for fam in FAMILIES.values() for m in fam]
    right_per_training = {name: [] for name in args.pipelines}
    subsets_per_training = []  # --feature-subsets: {subset: (pairs right, balanced accuracy)} per training
    if args.feature_subsets:
        from sklearn_hardness.features import ContactProfileFeatures

        real_features = ContactProfileFeatures().fit_transform(real.videos)
    for seeds in trainings:
        reset_peak()
        t1 = time.perf_counter()
        videos, target, groups = [], [], []
        for s in seeds:
            v, y, hardness, names, obj = simulated(s, cache=args.cache, **params)
            videos += v
            target.append(y)
            groups += [f"{s}-{o}" for o in obj]
        target = np.concatenate(target)
        say(f"\nsimulated everyday{' ' + str(params) if params else ''}, seeds "
            f"{seeds}: {len(videos)} presses "
            f"({dict(Counter(names[target].tolist()))}), {time.perf_counter() - t1:.1f} s, "
            f"peak RSS {peak_rss_mb():.0f} MB")
        say(f"\n| pipeline | balls | foam bricks | all 9 pairs | expected rank per object "
            f"({', '.join(members)}) | fit + predict s | peak RSS MB |")
        say("|---|---|---|---|---|---|---|")
        for name in args.pipelines:
            reset_peak()
            t1 = time.perf_counter()
            est = named_pipeline(name, args.seed).fit(videos, target)
            scores, fams = order_report(name, est, real, hardness)
            seconds = time.perf_counter() - t1
            right = sum(r for r, _, _ in fams.values())
            total = sum(n for _, n, _ in fams.values())
            right_per_training[name].append(right)
            ranks = ", ".join(f"{fams[f][2][m]:.2f}" for f in FAMILIES for m in FAMILIES[f] if m in fams[f][2])
            say(f"| {name} | {fams['balls'][0]}/{fams['balls'][1]} | "
                f"{fams['foam bricks'][0]}/{fams['foam bricks'][1]} | {right}/{total} | {ranks} | "
                f"{seconds:.0f} | {peak_rss_mb():.0f} |")
        if args.feature_subsets:
            subsets_per_training.append(feature_subsets(videos, target, np.asarray(groups), real, real_features,
                                                        hardness, say))
    if args.each_seed:
        # total: the pairs of the families present in --data (9 with the whole example_data)
        say(f"\nWithin-family pairs ordered right (of {total}), trained on each simulated set alone "
            f"({'gel ROI' if args.roi else 'full frame'})")
        say("\n| pipeline | " + " | ".join(f"seed {s}" for s in args.sim_seeds)
            + f" | mean | sets with {total}/{total} |")
        say("|---|" + "---|" * (len(args.sim_seeds) + 2))
        for name, rights in right_per_training.items():
            say(seed_row(name, rights, total, f"{sum(r == total for r in rights)} of {len(rights)}"))
        if subsets_per_training:
            say(f"\nContactProfileFeatures subsets (balanced logistic regression): within-family pairs ordered "
                f"right (of {total}) per simulated set, and the mean object-disjoint balanced accuracy on them")
            say("\n| ContactProfileFeatures used | " + " | ".join(f"seed {s}" for s in args.sim_seeds)
                + " | mean | everyday bal. acc. (mean) |")
            say("|---|" + "---|" * (len(args.sim_seeds) + 2))
            for subset in subsets_per_training[0]:
                rights = [per[subset][0] for per in subsets_per_training]
                accs = [per[subset][1] for per in subsets_per_training]
                say(seed_row(subset, rights, total, f"{np.mean(accs):.3f}"))
    say(f"\ntotal {time.perf_counter() - t0:.0f} s")
    if args.out:
        write_output(args.out, "\n".join(out))


if __name__ == "__main__":
    main()
