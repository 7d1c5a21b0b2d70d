"""skorch callbacks of the experiments' nets."""

from __future__ import annotations

from skorch.callbacks import EarlyStopping

__all__ = ["EarlyStoppingAfterFirstFit"]


class EarlyStoppingAfterFirstFit(EarlyStopping):
    """skorch's :class:`~skorch.callbacks.EarlyStopping` on every training call but the first.

    In active sampling a net is trained once on the initial presses, then
    again (``partial_fit``) after each query. The first call runs every epoch,
    so the paper's convergence rule (training loss <= 1 after it) keeps its
    meaning: stopped early, initial trainings can fail it (evidence:
    ``docs/user_guide/runtime.rst``). The calls after it stop once the
    monitored loss has not improved for ``patience`` epochs. The experiments'
    ``early_stopping=k`` adds it to their named nets.

    Parameters
    ----------
    monitor, patience, threshold, threshold_mode, sink, load_best
        As for :class:`skorch.callbacks.EarlyStopping`.

    Attributes
    ----------
    active_ : bool
        Whether it may stop the current training call (False during the
        first one, when the net has no history yet).

    Examples
    --------
    >>> from sklearn_hardness.models import OFNNClassifier
    >>> from sklearn_hardness.experiments._callbacks import EarlyStoppingAfterFirstFit
    >>> net = OFNNClassifier(max_epochs=50, callbacks=[
    ...     ("early_stopping", EarlyStoppingAfterFirstFit(monitor="train_loss", patience=3))])
    """

    def on_train_begin(self, net, **kwargs):
        super().on_train_begin(net, **kwargs)
        self.active_ = len(net.history) > 0  # empty at the first call: the initial training

    def on_epoch_end(self, net, **kwargs):
        if self.active_:
            super().on_epoch_end(net, **kwargs)
