"""The losses of Higginson's thesis (Sec. 2.1.2, 2.4.2, 3.4.1), with configurable weights.

All take tensors [B, C, H, W] (or [B, T, C, H, W] for the temporal loss) in the space the
model is trained in (for TNND: log(1 + radiance)).

* ``l1`` / ``mse``: per-pixel error.
* ``gradient`` (L_g, Eq. 2.1, after Chaitanya et al. 2017): L1 between the spatial gradients of
  the 3x3-Gaussian-blurred target and prediction. The thesis leaves the gradient operator open;
  we use forward differences (x and y) of the blurred image, borders replicated.
* ``temporal`` (L_t, Eq. 2.2): L1 between the frame-to-frame differences of prediction and
  target (P_t - P_{t-1} vs T_t - T_{t-1}).
* ``focal_frequency`` (Jiang et al. 2021, ICCV): the squared distance of the 2-D spectra,
  weighted per frequency by that distance to the power alpha (1), normalized to [0, 1] per
  image and not back-propagated through, so hard frequencies weigh more.
"""
from __future__ import annotations

from dataclasses import dataclass

import torch
import torch.nn.functional as F

GAUSSIAN_3X3 = torch.tensor([[1.0, 2.0, 1.0], [2.0, 4.0, 2.0], [1.0, 2.0, 1.0]]) / 16.0


def blur3x3(x: torch.Tensor) -> torch.Tensor:
    """3x3 binomial (Gaussian, sigma ~0.85 px) blur per channel, borders replicated."""
    c = x.shape[1]
    k = GAUSSIAN_3X3.to(x).expand(c, 1, 3, 3)
    return F.conv2d(F.pad(x, (1, 1, 1, 1), mode="replicate"), k, groups=c)


def forward_differences(x: torch.Tensor):
    """(x[:, :, :, 1:] - x[:, :, :, :-1], x[:, :, 1:, :] - x[:, :, :-1, :])."""
    return x[..., :, 1:] - x[..., :, :-1], x[..., 1:, :] - x[..., :-1, :]


def l1(p, t):
    return (p - t).abs().mean()


def mse(p, t):
    return ((p - t) ** 2).mean()


def gradient(p, t):
    """L_g: mean |grad g(T) - grad g(P)| over both directions."""
    px, py = forward_differences(blur3x3(p))
    tx, ty = forward_differences(blur3x3(t))
    return 0.5 * ((px - tx).abs().mean() + (py - ty).abs().mean())


def temporal(p, t):
    """L_t over clips [B, T, C, H, W] (T >= 2): mean |dP/dt - dT/dt|."""
    if p.shape[1] < 2:
        return p.new_zeros(())
    return ((p[:, 1:] - p[:, :-1]) - (t[:, 1:] - t[:, :-1])).abs().mean()


def focal_frequency(p, t, alpha: float = 1.0):
    """Focal frequency loss: mean over frequencies of w * |F(P) - F(T)|^2 with
    w = (|F(P) - F(T)|^2)^alpha / max, detached."""
    fp = torch.fft.fft2(p, norm="ortho")
    ft = torch.fft.fft2(t, norm="ortho")
    d = (fp - ft).abs() ** 2
    w = d.detach() ** alpha
    w = w / w.flatten(-2).amax(-1).clamp_min(1e-12)[..., None, None]
    return (w * d).mean()


@dataclass
class LossWeights:
    """Weights of L = w_mse L_mse + w_l1 L_1 + w_g L_g + w_t L_t + w_ffl L_ffl. TNND's defaults are
    the thesis's Eq. 2.18 (w1 L_mse + w2 L_g; the values are ours, the thesis gives none)."""
    mse: float = 1.0
    l1: float = 0.0
    gradient: float = 0.5
    temporal: float = 0.0
    ffl: float = 0.0

    @staticmethod
    def parse(text: str, base: "LossWeights | None" = None) -> "LossWeights":
        """'mse=1,gradient=0.5' -> LossWeights (unnamed terms keep `base`'s values)."""
        w = LossWeights(**vars(base)) if base else LossWeights()
        for item in filter(None, text.split(",")):
            k, _, v = item.partition("=")
            if k not in vars(w):
                raise ValueError(f"unknown loss '{k}' (expected one of {', '.join(vars(w))})")
            setattr(w, k, float(v))
        return w


def total_loss(pred: torch.Tensor, target: torch.Tensor, w: LossWeights) -> tuple[torch.Tensor, dict]:
    """pred/target: [B, T, C, H, W]. Returns the weighted sum and each term (floats)."""
    flat_p, flat_t = pred.flatten(0, 1), target.flatten(0, 1)
    terms = {}
    total = pred.new_zeros(())
    for name, weight, fn in (("mse", w.mse, lambda: mse(flat_p, flat_t)), ("l1", w.l1, lambda: l1(flat_p, flat_t)),
                             ("gradient", w.gradient, lambda: gradient(flat_p, flat_t)),
                             ("temporal", w.temporal, lambda: temporal(pred, target)),
                             ("ffl", w.ffl, lambda: focal_frequency(flat_p, flat_t))):
        if weight:
            v = fn()
            terms[name] = float(v.detach())
            total = total + weight * v
    return total, terms
