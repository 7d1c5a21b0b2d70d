"""MLP head on fixed features: OFNNClassifier, DINOv2NNClassifier and ContactProfileNNClassifier.

The three keep the paper's names (and ours for the contact-profile head) but are one
implementation, :class:`_MLPClassifier`, and one docstring, :data:`_MLP_DOCSTRING`; they
differ in their description, defaults and example.
"""

from __future__ import annotations

import inspect
import numbers
import textwrap

import numpy as np
import torch
from sklearn.utils.validation import check_array

from ..utils._param_validation import Interval
from ._mc_dropout import MCDropoutClassifierBase
from ._mc_sampling import MCDropout

__all__ = ["MLPHead", "OFNNClassifier", "DINOv2NNClassifier", "ContactProfileNNClassifier"]


class MLPHead(torch.nn.Module):
    """Two-layer classifier head: Linear -> ReLU -> dropout -> Linear.

    This is the paper's "2-layer NN with 128 neurons in the hidden layer,
    followed by a dropout layer". It returns logits.

    Parameters
    ----------
    input_dim : int
        Number of input features.
    n_classes : int
        Number of classes (output logits).
    hidden_units : int, default=128
        Width of the hidden layer.
    dropout : float, default=0.2
        Dropout probability after the hidden layer.
    """

    def __init__(self, input_dim, n_classes, hidden_units=128, dropout=0.2):
        super().__init__()
        self.hidden = torch.nn.Linear(int(input_dim), int(hidden_units))
        self.dropout = MCDropout(dropout)
        self.out = torch.nn.Linear(int(hidden_units), int(n_classes))

    def forward(self, X, n_replicas=1):
        """Logits of shape (n_replicas * n, n_classes).

        The hidden activations (deterministic) are computed once and tiled
        ``n_replicas`` times (replica-major) before dropout, so MC passes only
        re-run dropout and the output layer.
        """
        h = torch.relu(self.hidden(X))
        if n_replicas > 1:
            # a broadcast view, no copy: dropout's product materialises the replicas
            h = h.unsqueeze(0).expand(n_replicas, -1, -1)
            return self.out(self.dropout(h)).reshape(-1, self.out.out_features)
        return self.out(self.dropout(h))


class _MLPClassifier(MCDropoutClassifierBase):
    _parameter_constraints = {
        **MCDropoutClassifierBase._parameter_constraints,
        "hidden_units": [Interval(numbers.Integral, 1, None, closed="left")],
    }
    _input_meta_attrs = ("n_features_in_",)

    def __init__(
        self,
        module=MLPHead,
        *,
        hidden_units=128,
        dropout=0.2,
        class_weight=None,
        random_state=None,
        criterion=torch.nn.CrossEntropyLoss,
        optimizer=torch.optim.Adam,
        lr=1e-3,
        max_epochs=50,
        batch_size=32,
        train_split=None,
        classes=None,
        verbose=0,
        device="cpu",
        **kwargs,
    ):
        super().__init__(
            module,
            dropout=dropout,
            class_weight=class_weight,
            random_state=random_state,
            criterion=criterion,
            optimizer=optimizer,
            lr=lr,
            max_epochs=max_epochs,
            batch_size=batch_size,
            train_split=train_split,
            classes=classes,
            verbose=verbose,
            device=device,
            **kwargs,
        )
        self.hidden_units = hidden_units

    def _check_X(self, X, reset):
        # check_array first: a 1-D X gets scikit-learn's "Reshape your data" advice, and
        # array-likes (lists, wrappers) become arrays before their shape is looked at
        X = check_array(X, dtype=np.float32, ensure_all_finite=True, allow_nd=True, input_name="X")
        if X.ndim != 2:
            raise ValueError(
                f"{type(self).__name__} expects a 2-D array of features (n_samples, n_features); "
                f"got shape {X.shape}. Turn selected frames (n, k, H, W, C) into features first "
                "(OpticalFlowFeatures, DINOv2Features or ContactProfileFeatures), or use ConvLSTMClassifier."
            )
        if reset:
            self.n_features_in_ = X.shape[1]
        elif X.shape[1] != self.n_features_in_:
            raise ValueError(
                f"X has {X.shape[1]} features, but {type(self).__name__} is expecting "
                f"{self.n_features_in_} features as input."
            )
        return X

    def _placeholder_meta(self):
        return {"input_dim": 1, "n_classes": 2, "hidden_units": 1, "dropout": self.dropout}

    def _module_defaults(self):
        return {
            "input_dim": self.n_features_in_,
            "n_classes": len(self.classes_),
            "hidden_units": int(self.hidden_units),
            "dropout": self.dropout,
        }

    def _meta_from_state_dict(self, state_dict):
        self.n_features_in_ = int(state_dict["hidden.weight"].shape[1])
        return int(state_dict["out.weight"].shape[0])

    def _mc_bytes_per_row(self, X):
        # hidden activations, mask and product per replicated row
        return 4 * (3 * int(self.hidden_units) + 2 * len(self.classes_))


#: The docstring of the three MLP classifiers, filled per class by :func:`_mlp_docstring`.
_MLP_DOCSTRING = """{summary}

{description}

Parameters
----------
module : torch.nn.Module class, default=MLPHead
    Network; built at fit with ``input_dim``, ``n_classes``,
    ``hidden_units`` and ``dropout``. Its ``forward`` takes
    ``(X, n_replicas=1)``.
hidden_units : int, default={hidden_units}
    Width of the hidden layer{paper_hidden_units}.
dropout : float, default={dropout}
    Dropout probability after the hidden layer{paper_dropout}. A plain
    parameter, so ``GridSearchCV(pipe, {{"clf__dropout": [...]}})`` works;
    setting it on a fitted net changes the live dropout layers.
class_weight : dict, "balanced" or None, default=None
    Weights of the classes in the loss, as in scikit-learn
    (:func:`sklearn.utils.class_weight.compute_class_weight` on the
    cold-start training labels; with ``classes``, ``"balanced"``
    weighs the classes present and gives 1.0 to absent ones); a dict
    maps labels to weights.
random_state : int, RandomState instance or None, default=None
    Seeds the initial weights, the shuffling and the training dropout
    masks (without touching torch's global generator). ``None`` uses
    torch's global generator.
criterion : torch criterion class, default=torch.nn.CrossEntropyLoss
    The module returns logits; ``predict_proba`` applies softmax.
optimizer : torch optimizer class, default=torch.optim.Adam
lr : float, default={lr}
max_epochs : int, default={max_epochs}
    Epochs of ``fit``; {paper_epochs}.
batch_size : int, default={batch_size}
train_split : callable or None, default=None
    None trains on all of ``X``{paper_train_split}; see skorch.
classes : array-like or None, default=None
    All labels, if ``y`` may not contain every class, in any order
    (``classes_`` is them sorted).
verbose : int, default=0
device : {{"cpu", "cuda", "auto"}} or str, default="cpu"
    ``"auto"`` picks CUDA when available.
**kwargs
    Other skorch parameters (``callbacks``, ``iterator_train__*``,
    ``optimizer__*``, ``module__*``, ``warm_start``...).

Attributes
----------
classes_ : ndarray of shape (n_classes,)
    Class labels.
n_features_in_ : int
    Number of features seen during fit.
module_ : MLPHead
    The trained network.
history_ : skorch.History
    Per-epoch training loss (``train_loss``).
class_weight_ : ndarray of shape (n_classes,) or None
    Weights of the classes in the loss.
final_train_loss_ : float
    Training loss of the last epoch (see
    :func:`sklearn_hardness.models.is_converged`).
{see_also}
Examples
--------
{examples}
"""

#: What the paper says of its MLP head, where a class is the paper's (OFNN, DINOv2NN).
_PAPER_NOTES = {
    "paper_hidden_units": " (128 in the paper)",
    "paper_dropout": " (0.2 in the paper)",
    "paper_epochs": ("the paper trains the heads for 50 epochs initially, then 25 per "
                     "active-sampling round via ``partial_fit(X, y, epochs=25)``"),
    "paper_train_split": " (as the paper does)",
}
_OWN_NOTES = {
    "paper_hidden_units": "",
    "paper_dropout": "",
    "paper_epochs": "``partial_fit(X, y, epochs=...)`` continues",
    "paper_train_split": "",
}


def _mlp_docstring(summary, description, examples, *, paper, see_also=""):
    """Class decorator: the class's docstring from :data:`_MLP_DOCSTRING`.

    The three MLP classifiers share one implementation (:class:`_MLPClassifier`)
    and so one parameter list; this is its one text. The defaults it shows
    are read from the class's ``__init__``, so they cannot drift from the
    signature. ``paper`` adds what the paper says of its MLP head.
    """

    def decorate(cls):
        defaults = {name: p.default for name, p in inspect.signature(cls.__init__).parameters.items()}
        text = _MLP_DOCSTRING.format(
            summary=summary,
            description=textwrap.dedent(description).strip(),
            see_also=textwrap.dedent(see_also),
            examples=textwrap.dedent(examples).strip(),
            **{name: defaults[name] for name in ("hidden_units", "dropout", "lr", "max_epochs", "batch_size")},
            **(_PAPER_NOTES if paper else _OWN_NOTES),
        )
        # indented as a docstring written in the class body (what inspect.cleandoc expects)
        first, _, rest = text.partition("\n")
        cls.__doc__ = first + "\n" + textwrap.indent(rest, "    ", lambda line: line.strip() != "")
        return cls

    return decorate


@_mlp_docstring(
    "Optical-flow features + MLP head with MC dropout (the paper's OFNN).",
    """
    Input: 2-D features, e.g. the output of
    :class:`sklearn_hardness.features.OpticalFlowFeatures` (flattened
    Lucas-Kanade displacements). Standardising them (``StandardScaler``)
    before the net helps. The head is Linear(d, 128) -> ReLU -> dropout ->
    Linear(128, n_classes); :meth:`predict_proba_samples` gives MC-dropout
    samples for uncertainty.
    """,
    """
    >>> import numpy as np
    >>> from sklearn_hardness.models import OFNNClassifier
    >>> rng = np.random.default_rng(0)
    >>> X = rng.normal(size=(30, 20)).astype("float32")
    >>> y = np.repeat(["soft", "medium", "hard"], 10)
    >>> X[y == "hard"] += 2
    >>> clf = OFNNClassifier(max_epochs=30, random_state=0).fit(X, y)
    >>> clf.predict_proba_samples(X[:4], n_samples=10, random_state=0).shape
    (10, 4, 3)
    """,
    paper=True,
)
class OFNNClassifier(_MLPClassifier):
    pass


@_mlp_docstring(
    "DINOv2 features + MLP head with MC dropout (the paper's DINOv2NN).",
    """
    Input: 2-D features, e.g. the output of
    :class:`sklearn_hardness.features.DINOv2Features` (frozen DINOv2
    embeddings of the selected frames, concatenated). The backbone is not
    part of this net, so features are extracted once and MC sampling only
    re-runs the head. Same head as :class:`OFNNClassifier`.
    """,
    """
    >>> import numpy as np
    >>> from sklearn_hardness.models import DINOv2NNClassifier
    >>> rng = np.random.default_rng(0)
    >>> X = rng.normal(size=(30, 64)).astype("float32")
    >>> y = np.repeat([0, 1, 2], 10)
    >>> clf = DINOv2NNClassifier(max_epochs=5, random_state=0).fit(X, y)
    >>> clf.predict_proba(X[:2]).shape
    (2, 3)
    """,
    paper=True,
)
class DINOv2NNClassifier(_MLPClassifier):
    pass


@_mlp_docstring(
    "Contact-profile features + MLP head with MC dropout.",
    """
    Input: 2-D features of the loading phase, e.g. the twelve columns of
    :class:`sklearn_hardness.features.ContactProfileFeatures` (peak change,
    loading time, contact area and spread, how area grows with intensity,
    ...), which carry hardness across object shapes better than the frames
    themselves. Same head as :class:`OFNNClassifier` (Linear -> ReLU ->
    dropout -> Linear), sized for a handful of features: a narrower hidden
    layer, a higher learning rate and more epochs, so that
    :meth:`predict_proba_samples` gives MC-dropout samples for active
    sampling on the features that generalise to new objects.
    Standardise the features first (``StandardScaler``), as
    :func:`~sklearn_hardness.models.make_contact_profile_pipeline` does.
    """,
    """
    >>> import numpy as np
    >>> from sklearn_hardness.models import ContactProfileNNClassifier
    >>> rng = np.random.default_rng(0)
    >>> X = rng.normal(size=(30, 10)).astype("float32")
    >>> y = np.repeat([0, 1, 2], 10)
    >>> X[y == 2, 0] += 2
    >>> clf = ContactProfileNNClassifier(max_epochs=20, random_state=0).fit(X, y)
    >>> clf.predict_proba_samples(X[:4], n_samples=10, random_state=0).shape
    (10, 4, 3)
    """,
    paper=False,
    see_also="""
    See Also
    --------
    make_contact_profile_pipeline : Videos to this classifier in one pipeline.
    """,
)
class ContactProfileNNClassifier(_MLPClassifier):
    def __init__(
        self,
        module=MLPHead,
        *,
        hidden_units=64,
        dropout=0.2,
        class_weight=None,
        random_state=None,
        criterion=torch.nn.CrossEntropyLoss,
        optimizer=torch.optim.Adam,
        lr=3e-3,
        max_epochs=100,
        batch_size=32,
        train_split=None,
        classes=None,
        verbose=0,
        device="cpu",
        **kwargs,
    ):
        super().__init__(
            module,
            hidden_units=hidden_units,
            dropout=dropout,
            class_weight=class_weight,
            random_state=random_state,
            criterion=criterion,
            optimizer=optimizer,
            lr=lr,
            max_epochs=max_epochs,
            batch_size=batch_size,
            train_split=train_split,
            classes=classes,
            verbose=verbose,
            device=device,
            **kwargs,
        )
