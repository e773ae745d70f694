"""TNND, the Tiny Neural Network Denoiser of Higginson's thesis (Sec. 2.4): a neural cellular
automaton whose cells are the pixels of the 9-channel deep image.

State (Eq. 2.13): s = [c'_R, c'_G, c'_B, n_x, n_y, n_z, a_R, a_G, a_B] with c' = log(1 + c) of
the noisy radiance (emission taken out), n the view-space shading normal and a the albedo.

Perception (Eq. 2.15), 39 channels, in this order:
    s (9) | K_gauss * s[0:3] (3) | K_laplace * s (9) | K_sobel_x * s (9) | K_sobel_y * s (9)
with the 3x3 kernels (borders replicated; y grows downwards, x to the right)
    K_gauss   = [[1, 2, 1], [2, 4, 2], [1, 2, 1]] / 16
    K_laplace = [[1, 2, 1], [2, -12, 2], [1, 2, 1]] / 16   (= K_gauss - identity)
    K_sobel_x = [[-1, 0, 1], [-2, 0, 2], [-1, 0, 1]] / 8   (a ramp of slope 1 in x gives 1)
    K_sobel_y = K_sobel_x transposed                         (a ramp of slope 1 in y gives 1)

Rule and update (Eqs. 2.16, 2.17): s <- s + sigmoid(p W) + b with W 39x9 and b 1x9:
351 + 9 = 360 parameters (the thesis counts 351, the weights without the bias).

The same model runs in the library (src/methods/tnnd/), which reads `export_weights`'s file.
"""
from __future__ import annotations

import json

import torch
import torch.nn as nn
import torch.nn.functional as F

STATE = 9
PERCEPTION = 39

K_GAUSS = torch.tensor([[1.0, 2.0, 1.0], [2.0, 4.0, 2.0], [1.0, 2.0, 1.0]]) / 16.0
K_LAPLACE = torch.tensor([[1.0, 2.0, 1.0], [2.0, -12.0, 2.0], [1.0, 2.0, 1.0]]) / 16.0
K_SOBEL_X = torch.tensor([[-1.0, 0.0, 1.0], [-2.0, 0.0, 2.0], [-1.0, 0.0, 1.0]]) / 8.0
K_SOBEL_Y = K_SOBEL_X.t().contiguous()

WEIGHTS_FORMAT = "rtdenoise-tnnd-weights"
WEIGHTS_VERSION = 1


def perceive(s: torch.Tensor) -> torch.Tensor:
    """Perception vector [B, 39, H, W] of the state [B, 9, H, W] (Eq. 2.15)."""
    b, c, h, w = s.shape
    assert c == STATE, f"state has {c} channels, expected {STATE}"
    padded = F.pad(s, (1, 1, 1, 1), mode="replicate")
    kernels = torch.stack([K_LAPLACE, K_SOBEL_X, K_SOBEL_Y]).to(s)          # [3, 3, 3]
    filtered = F.conv2d(padded, kernels.repeat(c, 1, 1)[:, None], groups=c)  # [B, 27, H, W]: per channel L, Sx, Sy
    filtered = filtered.view(b, c, 3, h, w)
    gauss = F.conv2d(padded[:, :3], K_GAUSS.to(s).expand(3, 1, 3, 3), groups=3)
    return torch.cat([s, gauss, filtered[:, :, 0], filtered[:, :, 1], filtered[:, :, 2]], dim=1)


def encode(color, normal, albedo):
    """The initial state from the (emission-free) radiance, view-space normals and albedo, [B, 3, H, W] each."""
    return torch.cat([torch.log1p(color.clamp_min(0)), normal, albedo], dim=1)


def decode(state):
    """Radiance from the state's first three channels (clamped to >= 0 before expm1)."""
    return torch.expm1(state[:, :3].clamp_min(0))


class TNND(nn.Module):
    # Settings of the training runs (scripts/train.sh tnnd); recorded in the weights file.
    default_iterations = 12
    train_iterations = (8, 16)
    default_losses = "mse=1,gradient=0.5"  # Eq. 2.18 (the weights are ours)
    default_clip = 1

    def __init__(self, init_scale: float = 0.01, seed: int = 0):
        super().__init__()
        g = torch.Generator().manual_seed(seed)
        # sigmoid(0) = 0.5 and b = -0.5: the untrained automaton starts as the identity.
        self.W = nn.Parameter(torch.randn(PERCEPTION, STATE, generator=g) * init_scale)
        self.b = nn.Parameter(torch.full((STATE,), -0.5))

    def parameter_count(self) -> int:
        return sum(p.numel() for p in self.parameters())

    def rule_kernel(self) -> torch.Tensor:
        """p W as one 3x3 convolution of the state: the perception is linear in s, so
        (p W)_j = sum_c (W[c,j] delta + W[9+c,j] K_gauss [c<3] + W[12+c,j] K_laplace
        + W[21+c,j] K_sobel_x + W[30+c,j] K_sobel_y) * s_c. Returns the [9, 9, 3, 3] kernel
        (exactly the thesis's model, computed in one convolution; training is ~10x faster)."""
        w = self.W
        delta = torch.zeros(3, 3, dtype=w.dtype)
        delta[1, 1] = 1
        k = (w[:STATE].t()[:, :, None, None] * delta.to(w)
             + w[12:21].t()[:, :, None, None] * K_LAPLACE.to(w)
             + w[21:30].t()[:, :, None, None] * K_SOBEL_X.to(w)
             + w[30:39].t()[:, :, None, None] * K_SOBEL_Y.to(w))
        gauss = w[9:12].t()[:, :, None, None] * K_GAUSS.to(w)  # only the colour channels
        return k + F.pad(gauss, (0, 0, 0, 0, 0, STATE - 3))

    def step(self, s: torch.Tensor, kernel: torch.Tensor | None = None) -> torch.Tensor:
        """One iteration: s + sigmoid(p W) + b (Eqs. 2.16, 2.17)."""
        if kernel is None:
            kernel = self.rule_kernel()
        z = F.conv2d(F.pad(s, (1, 1, 1, 1), mode="replicate"), kernel)
        return s + torch.sigmoid(z) + self.b[None, :, None, None]

    def step_by_perception(self, s: torch.Tensor) -> torch.Tensor:
        """The same iteration written as Eqs. 2.15-2.17 (perception vector, then the rule)."""
        update = torch.sigmoid(torch.einsum("bkhw,kj->bjhw", perceive(s), self.W))
        return s + update + self.b[None, :, None, None]

    def forward(self, state: torch.Tensor, iterations: int) -> torch.Tensor:
        kernel = self.rule_kernel()
        for _ in range(iterations):
            state = self.step(state, kernel)
        return state

    # --- training interface (rtdenoise_train.train) ---------------------------------------
    def predict(self, batch: dict, iterations: int) -> torch.Tensor:
        """batch: tensors [B, T, C, H, W]; returns the log-space colour [B, T, 3, H, W]."""
        b, t = batch["color"].shape[:2]
        flat = {k: v.flatten(0, 1) for k, v in batch.items()}
        s = encode(flat["color"], flat["normal"], flat["albedo"])
        return self.forward(s, iterations)[:, :3].view(b, t, 3, *s.shape[-2:])

    @staticmethod
    def target(batch: dict) -> torch.Tensor:
        return torch.log1p(batch["reference"].clamp_min(0))

    def sample_iterations(self, rng) -> int:
        """Random iteration count per batch (as Mordvintsev et al.; the loss after the last)."""
        lo, hi = self.train_iterations
        return int(rng.integers(lo, hi + 1))

    def eval_iterations(self) -> int:
        return self.default_iterations

    # --- the library's weights file (docs/methods/tnnd.md) ----------------------------------
    def export_weights(self, path: str, training: dict | None = None) -> None:
        doc = {
            "format": WEIGHTS_FORMAT,
            "version": WEIGHTS_VERSION,
            "model": "TNND (Higginson 2023, Sec. 2.4)",
            "state": ["log1p(color.R)", "log1p(color.G)", "log1p(color.B)", "viewNormal.X", "viewNormal.Y",
                      "viewNormal.Z", "albedo.R", "albedo.G", "albedo.B"],
            "perception": "s(9), gauss(s[0:3])(3), laplace(s)(9), sobelX(s)(9), sobelY(s)(9)",
            "colorTransform": "log1p",
            "normalSpace": "view",
            "iterations": {"default": self.default_iterations, "train": list(self.train_iterations)},
            "W": [[float(v) for v in row] for row in self.W.detach().double().tolist()],
            "b": [float(v) for v in self.b.detach().double().tolist()],
            "training": training or {},
        }
        with open(path, "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")

    @staticmethod
    def load_weights(path: str) -> "TNND":
        with open(path) as f:
            doc = json.load(f)
        if doc.get("format") != WEIGHTS_FORMAT or doc.get("version") != WEIGHTS_VERSION:
            raise ValueError(f"{path}: not a version-{WEIGHTS_VERSION} {WEIGHTS_FORMAT} file")
        m = TNND()
        with torch.no_grad():
            m.W.copy_(torch.tensor(doc["W"]))
            m.b.copy_(torch.tensor(doc["b"]))
        return m
