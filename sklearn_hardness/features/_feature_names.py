"""Named output columns of the feature transformers: checking a ``features`` parameter."""

from __future__ import annotations

__all__ = ["check_feature_names", "feature_columns"]

def check_feature_names(features, known, *, param="features"):
    """The output columns a ``features`` parameter names, as a tuple, checked against ``known``.

    ``"all"`` gives ``known`` in its order; a sequence gives its names in its
    own order. Unknown, repeated or no names are an error that lists the
    known ones and names the parameter (``param``).
    """
    if isinstance(features, str):  # "all" (the constraint allows no other string)
        return tuple(known)
    features = tuple(features)
    unknown = [f for f in features if f not in known]
    repeated = sorted({f for f in features if features.count(f) > 1})
    if unknown or repeated or not features:
        problem = (f"got unknown {unknown}" if unknown else f"got {repeated} more than once" if repeated
                   else "got none")
        raise ValueError(f"{param} must be 'all' or a non-empty sequence of distinct names from {list(known)}; "
                         f"{problem}.")
    return features


def feature_columns(features, known):
    """The positions in ``known`` of the columns a ``features`` parameter names, in its order.

    Checked as :func:`check_feature_names` checks them (and raising its errors).
    """
    return [known.index(name) for name in check_feature_names(features, known)]
