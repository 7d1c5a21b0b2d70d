"""Random nuisance transforms of training frame sequences: :class:`FrameAugmenter`."""

from __future__ import annotations

import numbers

import torch
from sklearn.base import BaseEstimator

from ..utils._param_validation import Interval, validate_parameter_constraints

__all__ = ["FrameAugmenter"]


class FrameAugmenter(BaseEstimator):
    """Random nuisance transforms of frame sequences, drawn anew for every training batch.

    What changes between real recordings of one object and does not tell its
    hardness: where and which way round the contact lies in the frame, the
    sensor's optical gain (gel, lights, camera exposure), a slow drift of the
    exposure during a press, and pixel noise. A net trained on presses of a
    few dozen objects can learn any of them as a cue; drawing them at random
    for every batch takes that cue away. :class:`ConvLSTMClassifier` applies
    the augmenter passed as its ``augment`` parameter to each training batch
    (never to prediction or to the MC-dropout passes).

    Per press, the same for all its frames unless said otherwise:

    - ``flip``: mirrored left-right and up-down, each with probability 1/2;
    - ``shift``: moved by a whole number of pixels, drawn uniformly up to
      ``round(shift * H)`` rows and ``round(shift * W)`` columns either way;
      the border it uncovers repeats the edge pixels;
    - ``gain``: ``channels`` multiplied by ``g = exp(N(0, gain^2))``;
    - ``drift``: frame ``t`` of ``k`` multiplied by ``1 + d t / (k - 1)``,
      ``d ~ N(0, drift^2)`` (clipped so the factor stays positive);
    - ``noise``: Gaussian noise of s.d. ``noise`` added to ``channels``, per
      pixel and frame, in the units of the input.

    Channels that hold the logarithm of an intensity (the ones
    the ``IntensityChannels`` step of
    :func:`make_convlstm_pipeline` appends) are listed in ``log_channels``: the
    log of the gain (and drift) factor is added to them, so they stay the
    log statistics of the scaled frames (exactly where the change is well
    above the floor of ``IntensityChannels``).

    Parameters
    ----------
    flip : bool, default=True
        Random left-right and up-down mirroring.
    gain : float, default=0.2
        S.d. of the log gain per press (0.2: about +-20%).
    drift : float, default=0.0
        S.d. of the relative gain change from the first to the last frame.
    noise : float, default=0.0
        S.d. of additive pixel noise.
    shift : float in [0, 0.5), default=0.0
        Largest shift, as a fraction of the frame's height and width.
    channels : list of int or None, default=None
        Channels that gain, drift and noise act on; None: every channel not
        in ``log_channels``.
    log_channels : list of int, default=()
        Channels that hold log intensities: the log gain is added to them.

    Notes
    -----
    On simulated new objects and on real GelSight Wedge grasps,
    ``flip=True, gain=0.2`` gave no measurable gain over training without
    it (paired runs, within the spread of seeds), so
    ``make_convlstm_pipeline`` leaves it off by default (evidence:
    ``studies/pages/convlstm_augmentation.md``). The test
    ``tests/test_models_augmentation.py`` shows what it is for: a
    brightness that tells the class in training and not at test.

    See Also
    --------
    ConvLSTMClassifier : Takes it as ``augment``.
    make_convlstm_pipeline : ``augment=True`` sets the channels for its input.

    Examples
    --------
    >>> import torch
    >>> from sklearn_hardness.models import FrameAugmenter
    >>> X = torch.ones(2, 3, 4, 5, 1)
    >>> aug = FrameAugmenter(gain=0.5, noise=0.0)
    >>> out = aug.augment(X, generator=torch.Generator().manual_seed(0))
    >>> out.shape
    torch.Size([2, 3, 4, 5, 1])
    >>> bool(torch.allclose(out[0], out[0, 0, 0, 0, 0]))  # one gain per press
    True
    """

    _parameter_constraints = {
        "flip": ["boolean"],
        "gain": [Interval(numbers.Real, 0, None, closed="left")],
        "drift": [Interval(numbers.Real, 0, None, closed="left")],
        "noise": [Interval(numbers.Real, 0, None, closed="left")],
        "shift": [Interval(numbers.Real, 0, 0.5, closed="left")],
        "channels": [list, tuple, None],
        "log_channels": [list, tuple],
    }

    def __init__(self, *, flip=True, gain=0.2, drift=0.0, noise=0.0, shift=0.0, channels=None, log_channels=()):
        self.flip = flip
        self.gain = gain
        self.drift = drift
        self.noise = noise
        self.shift = shift
        self.channels = channels
        self.log_channels = log_channels

    def check(self, n_channels):
        """Validate the parameters for input with ``n_channels`` channels.

        Called by :class:`ConvLSTMClassifier` at ``fit``, so a bad value is
        reported before any training.

        Parameters
        ----------
        n_channels : int
            Channels of the input frames.

        Returns
        -------
        channels, log_channels : lists of int
            The resolved channel indices.
        """
        validate_parameter_constraints(
            self._parameter_constraints, self.get_params(deep=False), caller_name=type(self).__name__
        )
        log_channels = self._indices(self.log_channels, "log_channels", n_channels)
        if self.channels is None:
            channels = [c for c in range(n_channels) if c not in log_channels]
        else:
            channels = self._indices(self.channels, "channels", n_channels)
        both = sorted(set(channels) & set(log_channels))
        if both:
            raise ValueError(f"channels {both} are listed in both channels and log_channels.")
        return channels, log_channels

    def _shifted(self, X, generator):
        """``X`` (n, k, H, W, C) with each press moved by its own random offset (edges repeated)."""
        n, _, H, W, _ = X.shape
        dy_max, dx_max = round(self.shift * H), round(self.shift * W)
        dy = torch.randint(-dy_max, dy_max + 1, (n,), generator=generator)
        dx = torch.randint(-dx_max, dx_max + 1, (n,), generator=generator)
        # clamped source indices: the pixel shifted to (r, c) and, past the border, the edge pixel
        rows = (torch.arange(H)[None, :] - dy[:, None]).clamp_(0, H - 1).to(X.device)
        cols = (torch.arange(W)[None, :] - dx[:, None]).clamp_(0, W - 1).to(X.device)
        press = torch.arange(n, device=X.device)[:, None, None]
        # advanced indices around a slice come first: (n, H, W) + (k, C)
        return X[press, :, rows[:, :, None], cols[:, None, :]].permute(0, 3, 1, 2, 4).contiguous()

    @staticmethod
    def _indices(values, name, n_channels):
        out = []
        for v in values:
            if isinstance(v, bool) or not isinstance(v, numbers.Integral) or not 0 <= v < n_channels:
                raise ValueError(
                    f"{name} must hold channel indices in [0, {n_channels}) for input with {n_channels} "
                    f"channel(s), got {list(values)!r}."
                )
            out.append(int(v))
        if len(set(out)) != len(out):
            raise ValueError(f"{name} lists a channel twice: {list(values)!r}.")
        return out

    def augment(self, X, generator=None):
        """Return a randomly transformed copy of a batch of frame sequences.

        Parameters
        ----------
        X : torch.Tensor of shape (n, k, H, W, C)
            Frames, channels last (the input of :class:`ConvLSTMClassifier`).
        generator : torch.Generator or None, default=None
            CPU generator the random draws come from (None: torch's global one).

        Returns
        -------
        X_aug : torch.Tensor of the same shape, dtype and device
        """
        if X.dim() != 5:
            raise ValueError(f"X must be (n, k, H, W, C) frames, got shape {tuple(X.shape)}.")
        n, k, _, _, C = X.shape
        channels, log_channels = self.check(C)
        dev, dtype = X.device, X.dtype
        # flips, gains and drifts are drawn whatever the settings, so turning one on leaves the others'
        # draws as they were; the noise and then the shifts, drawn last, only when they are used
        flips = torch.rand(n, 2, generator=generator) < 0.5
        log_gain = torch.randn(n, generator=generator, dtype=torch.float64) * float(self.gain)
        slope = torch.randn(n, generator=generator, dtype=torch.float64) * float(self.drift)
        noise = torch.randn(X.shape, generator=generator, dtype=torch.float32) if self.noise > 0 else None
        out = X.clone()
        if self.flip:
            for axis, dim in ((0, 3), (1, 2)):  # left-right (W), up-down (H)
                rows = flips[:, axis].to(dev)
                if rows.any():
                    out[rows] = out[rows].flip(dim)
        if self.shift > 0:
            out = self._shifted(out, generator)
        t = torch.arange(k, dtype=torch.float64) / max(k - 1, 1)
        factor = torch.exp(log_gain)[:, None] * (1.0 + slope[:, None] * t[None, :]).clamp_min(0.05)  # (n, k)
        if channels == list(range(C)):  # every channel: in place, without gathering and scattering them
            if self.gain > 0 or self.drift > 0:
                out.mul_(factor.to(device=dev, dtype=dtype)[:, :, None, None, None])
            if noise is not None:
                out.add_(float(self.noise) * noise.to(dev, dtype))
        elif channels:
            f = factor.to(device=dev, dtype=dtype)[:, :, None, None]
            out[..., channels] = out[..., channels] * f[..., None]
            if noise is not None:
                out[..., channels] = out[..., channels] + float(self.noise) * noise.to(dev, dtype)[..., channels]
        if log_channels:
            out[..., log_channels] = out[..., log_channels] + torch.log(factor).to(dev, dtype)[:, :, None, None, None]
        return out
