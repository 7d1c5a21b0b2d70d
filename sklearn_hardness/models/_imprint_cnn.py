"""A small CNN trained from scratch on the imprint's frames: ImprintCNN and ImprintCNNClassifier."""

from __future__ import annotations

import math
import numbers

import numpy as np
import torch

from ..utils._param_validation import HasMethods, Interval
from ._augmentation import FrameAugmenter
from ._frames_net import FramesNetMixin, register_input_buffers
from ._mc_dropout import MCDropoutClassifierBase
from ._mc_sampling import MCDropout

__all__ = ["ImprintCNN", "ImprintCNNClassifier", "PressFrames"]

#: The transforms of ``augment=True``: :class:`FrameAugmenter` parameters; ``noise`` in units of the
#: standardised input (multiplied by the training frames' s.d. when the net standardises).
DEFAULT_AUGMENTATION = {"flip": True, "gain": 0.3, "shift": 0.125, "noise": 0.05}


class ImprintCNN(torch.nn.Module):
    """Four 3x3 convolution blocks, global average pooling, dropout and a linear head, per frame.

    Block ``i`` is a 3x3 convolution (``width``, ``2 width``, ``4 width``,
    ``4 width`` channels), batch normalisation and ReLU; a 2x2 max-pool
    (rounding up, so any frame size works) follows each of the first three.
    The pooled features go through one dropout layer before the linear
    head, so that its masks reach the output (MC dropout varies it).

    Every frame of a press is classified on its own; the press's output is
    the logarithm of the mean of its frames' class probabilities, so its
    softmax is that mean, and for a one-frame press it is the frame's
    log-softmax (a cross-entropy loss on it is the loss of the frame's
    logits).

    Parameters
    ----------
    in_channels : int
        Colour channels of the frames.
    n_classes : int
        Number of classes.
    width : int, default=16
        Channels of the first block.
    dropout : float, default=0.3
        Dropout probability on the pooled features.
    input_shape : tuple of int or None, default=None
        The (k, H, W, C) seen during fit, kept as a buffer (not used in the
        computation).
    input_mean, input_scale : sequence of float or None, default=None
        Per-channel statistics; the input is standardised as
        ``(X - input_mean) / input_scale``. None means 0 and 1.
    """

    def __init__(self, in_channels, n_classes, width=16, dropout=0.3, input_shape=None, input_mean=None,
                 input_scale=None):
        super().__init__()
        w = int(width)
        chans = (int(in_channels), w, 2 * w, 4 * w, 4 * w)
        layers = []
        for i in range(4):
            layers += [torch.nn.Conv2d(chans[i], chans[i + 1], 3, padding=1, bias=False),
                       torch.nn.BatchNorm2d(chans[i + 1]), torch.nn.ReLU(inplace=True)]
            if i < 3:
                layers.append(torch.nn.MaxPool2d(2, ceil_mode=True))
        self.features = torch.nn.Sequential(*layers)
        self.dropout = MCDropout(dropout)
        self.head = torch.nn.Linear(chans[-1], int(n_classes))
        register_input_buffers(self, in_channels, input_shape, input_mean, input_scale)

    def forward(self, X, n_replicas=1):
        """Log mean class probabilities of each press's frames, (n_replicas * B, n_classes), replica-major.

        Parameters
        ----------
        X : torch.Tensor of shape (B, k, H, W, C)
            Presses of ``k`` frames, channels last.
        n_replicas : int, default=1
            MC-dropout passes: the convolutions run once, the pooled
            features are tiled ``n_replicas`` times (row ``r * B + i`` of
            the output is pass ``r`` of press ``i``), each row with its own
            dropout masks.

        Returns
        -------
        log_proba : torch.Tensor of shape (n_replicas * B, n_classes)
        """
        B, k, H, W, C = X.shape
        x = ((X - self.input_mean) / self.input_scale).reshape(B * k, H, W, C).permute(0, 3, 1, 2)
        pooled = self.features(x).mean(dim=(-2, -1))  # (B k, F)
        if n_replicas > 1:
            pooled = pooled.repeat(n_replicas, 1)
        log_p = torch.log_softmax(self.head(self.dropout(pooled)), dim=-1)
        return torch.logsumexp(log_p.reshape(n_replicas * B, k, -1), dim=1) - math.log(k)


class PressFrames(torch.utils.data.Dataset):
    """The frames of a dataset of presses, one example each, labelled with their press's label.

    Item ``i`` is frame ``i % k`` of press ``i // k`` as a one-frame press
    ``(1, H, W, C)``, with the press's target; so there are ``k`` times as
    many examples as presses.

    Parameters
    ----------
    presses : torch.utils.data.Dataset
        Items ``(X_i, y_i)`` with ``X_i`` of shape (k, H, W, C), the same
        ``k`` for all (as ``ImprintCNNClassifier.get_dataset`` builds).
    """

    def __init__(self, presses):
        self.presses = presses
        self.n_frames = len(presses[0][0]) if len(presses) else 0

    def __len__(self):
        return len(self.presses) * self.n_frames

    def __getitem__(self, i):
        Xi, yi = self.presses[i // self.n_frames]
        j = i % self.n_frames
        return Xi[j : j + 1], yi


class ImprintCNNClassifier(FramesNetMixin, MCDropoutClassifierBase):
    """A small CNN trained from scratch on every frame of a press, with strong augmentation and MC dropout.

    Reads what the imprint looks like (its texture and shape, which tell the
    material) rather than how it changes over the press: in training every
    one of the ``k`` frames of a press is one example labelled with its
    press's label (``k`` times as many examples as presses); at prediction
    a press's class probabilities are the mean of its frames'. Takes
    (n, k, H, W, C) float32 frames, e.g. the output of
    :class:`~sklearn_hardness.preprocessing.ContactFrameSelector`; the input
    is standardised per channel inside the net with statistics of the first
    training data (``standardize``). No pretrained weights.

    The net (``ImprintCNN``): four blocks of a 3x3 convolution
    (``width``, ``2 width``, ``4 width``, ``4 width`` channels), batch
    normalisation and ReLU, a 2x2 max-pool after each of the first three,
    global average pooling, dropout and a linear head.

    Parameters
    ----------
    module : torch.nn.Module class, default=ImprintCNN
        Network; built at fit with ``in_channels``, ``n_classes``, ``width``,
        ``dropout``, ``input_shape``, ``input_mean`` and ``input_scale``. Its
        ``forward(X, n_replicas=1)`` takes presses (B, k, H, W, C) and
        returns the log of their mean class probabilities.
    width : int, default=16
        Channels of the first convolution block (the next ones have 2, 4 and
        4 times as many).
    dropout : float, default=0.3
        Dropout probability on the pooled features of each frame, before the
        head, so that the MC passes of :meth:`predict_proba_samples` differ.
        A plain parameter: ``GridSearchCV(pipe, {"clf__dropout": [...]})``.
    augment : bool or FrameAugmenter, default=True
        Random transforms of every training frame, drawn anew each time,
        never applied to prediction or to the MC passes. True: each frame
        independently

        - mirrored left-right and up-down, each with probability 1/2 (the
          contact's orientation tells nothing);
        - multiplied by a gain ``exp(N(0, 0.3^2))`` (how hard a hand
          presses, the sensor's optical gain);
        - moved by up to 1/8 of its height and width either way, whole
          pixels, edges repeated (where on the gel the object lands);
        - given Gaussian pixel noise of s.d. 0.05 of the standardised input
          (0.05 times the training frames' s.d. when ``standardize=True``;
          with ``standardize=False`` the input is taken to be unit-variance,
          as the ``FrameScaler`` of :func:`make_imprint_cnn_pipeline` makes it).

        False or None: none. A :class:`FrameAugmenter` (or any object with
        ``augment(X, generator)`` on (n, 1, H, W, C) one-frame presses) is
        used as given.
    standardize : bool, default=True
        Standardise the input per channel with the mean and standard
        deviation of the training frames of the cold-start ``fit``; buffers
        of the module, so saved parameters and pickles carry them.
    class_weight : dict, "balanced" or None, default="balanced"
        Weights of the classes in the loss (the criterion's ``weight``),
        from the cold-start training labels, as in scikit-learn; every frame
        carries its press's weight. Balanced by default: hardness ranks are
        imbalanced.
    random_state : int, RandomState instance or None, default=None
        Seeds the initial weights, the shuffling of the frames, the training
        dropout masks and the augmentations (without touching torch's global
        generator).
    criterion : torch criterion class, default=torch.nn.CrossEntropyLoss
    optimizer : torch optimizer class, default=torch.optim.AdamW
        With ``optimizer__weight_decay=1e-3`` unless given.
    lr : float, default=2e-3
    max_epochs : int, default=8
        Epochs of ``fit``; each sees every frame of every press once.
    batch_size : int, default=64
        Frames per training batch; presses per prediction batch.
    train_split : callable or None, default=None
        None trains on all of ``X``. A skorch split validates on whole
        presses (the loss of their mean probabilities).
    classes : array-like or None, default=None
        All labels, if ``y`` may not contain every class.
    verbose : int, default=0
    device : {"cpu", "cuda", "auto"} or str, default="cpu"
    **kwargs
        Other skorch parameters (``callbacks``, ``optimizer__*``...).

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
    n_frames_in_ : int
        Frames per press seen during fit.
    frame_shape_ : tuple of int
        (H, W, C) seen during fit.
    input_mean_, input_scale_ : ndarray of shape (C,)
        Standardisation of the input (0 and 1 with ``standardize=False``).
    class_weight_ : ndarray of shape (n_classes,) or None
        Weights of the classes in the loss.
    module_ : ImprintCNN
    history_ : skorch.History

    See Also
    --------
    make_imprint_cnn_pipeline : Videos -> frames -> this classifier.
    ConvLSTMClassifier : The paper's net, on the frames as a sequence.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.models import ImprintCNNClassifier
    >>> rng = np.random.default_rng(0)
    >>> X = rng.normal(size=(8, 3, 16, 20, 1)).astype("float32")
    >>> y = np.array([0, 1] * 4)
    >>> clf = ImprintCNNClassifier(width=4, max_epochs=2, random_state=0).fit(X, y)
    >>> clf.predict_proba(X[:2]).shape
    (2, 2)
    >>> clf.predict_proba_samples(X[:2], n_samples=5, random_state=0).shape
    (5, 2, 2)
    """

    _parameter_constraints = {
        **MCDropoutClassifierBase._parameter_constraints,
        "width": [Interval(numbers.Integral, 1, None, closed="left")],
        "standardize": ["boolean"],
        "augment": ["boolean", HasMethods(["augment"]), None],
    }

    def __init__(
        self,
        module=ImprintCNN,
        *,
        width=16,
        dropout=0.3,
        augment=True,
        standardize=True,
        class_weight="balanced",
        random_state=None,
        criterion=torch.nn.CrossEntropyLoss,
        optimizer=torch.optim.AdamW,
        lr=2e-3,
        max_epochs=8,
        batch_size=64,
        train_split=None,
        classes=None,
        verbose=0,
        device="cpu",
        **kwargs,
    ):
        kwargs.setdefault("optimizer__weight_decay", 1e-3)
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
        self.width = width
        self.augment = augment
        self.standardize = standardize

    def get_iterator(self, dataset, training=False):
        """skorch's iterator; in training over the presses' frames (``PressFrames``), shuffled.

        Parameters
        ----------
        dataset : torch.utils.data.Dataset
            Presses and their labels (:meth:`get_dataset`).
        training : bool, default=False
            True: one example per frame; False: whole presses.

        Returns
        -------
        iterator : torch.utils.data.DataLoader
        """
        if training:
            dataset = PressFrames(dataset)
        return super().get_iterator(dataset, training=training)

    def _training_augmenter(self):
        if isinstance(self.augment, (bool, np.bool_)):
            if not self.augment:
                return None
            params = dict(DEFAULT_AUGMENTATION)
            if self.standardize:
                params["noise"] *= float(np.sqrt(np.mean(np.square(self.input_scale_))))
            return FrameAugmenter(**params)
        return self.augment

    def _placeholder_meta(self):
        return {"in_channels": 1, "n_classes": 2, "width": 1, "dropout": self.dropout}

    def _module_defaults(self):
        return {
            "in_channels": self.frame_shape_[-1],
            "n_classes": len(self.classes_),
            "width": int(self.width),
            "dropout": self.dropout,
            **self._input_buffers(),
        }

    def _mc_bytes_per_row(self, X):
        # pooled features, mask and product, and the logits, of each frame of a replicated press
        k = X.shape[1]
        return 4 * 3 * k * (4 * int(self.width) + len(self.classes_))
