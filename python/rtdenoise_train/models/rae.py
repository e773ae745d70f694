"""RAE, the recurrent denoising autoencoder of Chaitanya et al. (2017) as Higginson's thesis
describes it (Sec. 2.1, 3.4), sized for CPU training here (docs/methods/rae.md has every choice
and its reason).

Inputs per frame (each [B, 3, H, W]): the noisy radiance c (emission taken out), the albedo a
and the view-space normal n; `inputs` selects ("color",), ("color", "albedo") or all three.
With the albedo the colour is demodulated: the network sees log(1 + c / k) with
k = clamp(a, 0, 1) + eps and its output y is remodulated, radiance = k (e^y - 1) with y clamped
to [0, Y_MAX]; without the albedo, log(1 + c) and e^y - 1. (The clamps keep out-of-domain input,
which the library's import lets through, from overflowing: they never act on the data set.)

Architecture, L = len(channels) levels, C_l channels at 1/2^l resolution:

    encoder level l (recurrent block):  u_0 = x, u_l = maxpool2(h_{l-1})
        a_l = act(conv_in_l(u_l))                    3x3 "same", C_l
        h_l = act(conv_rec_l(cat(a_l, h_l^{t-1})))   3x3 "same", C_l: the new hidden state
    decoder level l = L-2 .. 0:  d_{L-1} = h_{L-1}
        g_l = cat(up2(d_{l+1}), h_l, f_l)            f_l: albedo/normal avg-pooled to level l
        d_l = act(conv_a_l(g_l)),  d_l = conv_b_l(d_l) (act for l > 0; C_l, or 3 at l = 0)

act = leaky ReLU (slope 0.1), up2 = bilinear x2 (half-pixel centres, edges replicated, as
F.interpolate(align_corners=False)), maxpool2 / avgpool2 = 2x2 windows, stride 2. Frames are
padded (edges replicated) to a multiple of 2^(L-1) and the output cropped. The hidden states
h_l^{t-1} are zero on the first frame (the library's reset()).

The same model runs in the library (src/methods/rae/), which reads `export_weights`'s file.
"""
from __future__ import annotations

import base64
import json

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

WEIGHTS_FORMAT = "rtdenoise-rae-weights"
WEIGHTS_VERSION = 1
Y_MAX = 12.0  # log(1 + 65504 / 0.01) ~ 15.7 is the largest input; radiance e^12 ~ 1.6e5 caps the output
INPUT_SETS = {"color": ("color",), "color+albedo": ("color", "albedo"),
              "color+albedo+normal": ("color", "albedo", "normal")}


def up2(x: torch.Tensor) -> torch.Tensor:
    return F.interpolate(x, scale_factor=2, mode="bilinear", align_corners=False)


class RAE(nn.Module):
    # Defaults of the committed weights (docs/methods/rae.md "Size").
    default_channels = (12, 16, 24, 32)
    # Training defaults (train.py uses them when --losses / --clip are not given): Chaitanya et
    # al.'s weights w_s = 0.8 (L1), w_g = 0.1, w_t = 0.1; clips of 4 frames (the data set's
    # training sequences are 4 frames long).
    default_losses = "mse=0,l1=0.8,gradient=0.1,temporal=0.1"
    default_clip = 4

    def __init__(self, inputs=("color", "albedo", "normal"), channels=default_channels, slope: float = 0.1,
                 epsilon: float = 0.01, seed: int = 0):
        super().__init__()
        if isinstance(inputs, str):
            inputs = INPUT_SETS[inputs]
        self.inputs = tuple(inputs)
        if self.inputs not in INPUT_SETS.values():
            raise ValueError(f"inputs {inputs}: expected one of {', '.join(INPUT_SETS)}")
        self.features = tuple(k for k in ("albedo", "normal") if k in self.inputs)
        self.demodulate = "albedo" in self.inputs
        self.channels = tuple(int(c) for c in channels)
        self.slope, self.epsilon = float(slope), float(epsilon)
        if len(self.channels) < 2:
            raise ValueError("the RAE needs at least 2 levels")
        nf = 3 * len(self.features)
        cin = 3 + nf
        c = self.channels
        conv = lambda i, o: nn.Conv2d(i, o, 3, padding=1)
        with torch.random.fork_rng():  # seeded initialisation without touching the caller's stream
            torch.manual_seed(seed)
            self.enc_in = nn.ModuleList([conv(cin if l == 0 else c[l - 1], c[l]) for l in range(len(c))])
            self.enc_rec = nn.ModuleList([conv(2 * c[l], c[l]) for l in range(len(c))])
            self.dec_a = nn.ModuleList([conv(c[l + 1] + c[l] + nf, c[l]) for l in range(len(c) - 1)])
            self.dec_b = nn.ModuleList([conv(c[l], c[l] if l else 3) for l in range(len(c) - 1)])

    @property
    def levels(self) -> int:
        return len(self.channels)

    @property
    def multiple(self) -> int:
        """Frames are padded to a multiple of this (2^(levels-1))."""
        return 1 << (self.levels - 1)

    def parameter_count(self) -> int:
        return sum(p.numel() for p in self.parameters())

    def act(self, x):
        return F.leaky_relu(x, self.slope)

    # --- one frame ------------------------------------------------------------------------
    def encode(self, color, albedo=None, normal=None):
        """Network input x and decoder features f of unpadded buffers [B, 3, H, W]."""
        if albedo is not None:
            albedo = albedo.clamp(0, 1)  # the trained domain (a no-op on the renderer's albedo)
        k = albedo + self.epsilon if self.demodulate else 1.0
        x = [torch.log1p(color.clamp_min(0) / k)]
        f = [{"albedo": albedo, "normal": normal}[n] for n in self.features]
        return torch.cat(x + f, 1), (torch.cat(f, 1) if f else None)

    def step(self, x, f, hidden):
        """One frame through the network on padded x [B, cin, H, W] (H, W multiples of
        `multiple`); hidden: list of the levels' previous states or None (zeros). Returns the
        output y [B, 3, H, W] and the new hidden states."""
        hs = []
        u = x
        for l in range(self.levels):
            if l:
                u = F.max_pool2d(hs[-1], 2)
            a = self.act(self.enc_in[l](u))
            prev = hidden[l] if hidden is not None else torch.zeros_like(a)
            hs.append(self.act(self.enc_rec[l](torch.cat([a, prev], 1))))
        fl = [f]
        for _ in range(self.levels - 2):
            fl.append(F.avg_pool2d(fl[-1], 2) if f is not None else None)
        d = hs[-1]
        for l in reversed(range(self.levels - 1)):
            parts = [up2(d), hs[l]] + ([fl[l]] if f is not None else [])
            d = self.act(self.dec_a[l](torch.cat(parts, 1)))
            d = self.dec_b[l](d)
            if l:
                d = self.act(d)
        return d, hs

    def pad(self, t):
        h, w = t.shape[-2:]
        m = self.multiple
        return F.pad(t, (0, (-w) % m, 0, (-h) % m), mode="replicate")

    def decode(self, y, albedo=None, clamp: bool = True):
        """Radiance from the output y (cropped); clamp=False keeps e^y - 1 < 0 (training)."""
        e = torch.expm1(y.clamp(0, Y_MAX) if clamp else y)
        return e * (albedo.clamp(0, 1) + self.epsilon) if self.demodulate else e

    def forward(self, color, albedo=None, normal=None, hidden=None, clamp: bool = True):
        """One frame: radiance [B, 3, H, W] and the new hidden states."""
        h, w = color.shape[-2:]
        x, f = self.encode(color, albedo, normal)
        y, hs = self.step(self.pad(x), self.pad(f) if f is not None else None, hidden)
        return self.decode(y[..., :h, :w], albedo, clamp), hs

    def sequence(self, batch: dict, clamp: bool = True) -> torch.Tensor:
        """Radiance of every frame of clips [B, T, 3, H, W], the hidden state carried from
        frame to frame (zero before the first)."""
        hidden = None
        out = []
        for t in range(batch["color"].shape[1]):
            frame = {k: batch[k][:, t] for k in ("color", "albedo", "normal")}
            r, hidden = self.forward(frame["color"], frame["albedo"], frame["normal"], hidden, clamp)
            out.append(r)
        return torch.stack(out, 1)

    # --- training interface (rtdenoise_train.train) ---------------------------------------
    def predict(self, batch: dict, iterations: int = 0) -> torch.Tensor:
        """log(1 + radiance) of every frame [B, T, 3, H, W] (the loss space). Radiance below
        0 is kept down to -0.5 so that its gradient is not cut (the library clamps at 0)."""
        return torch.log1p(self.sequence(batch, clamp=False).clamp_min(-0.5))

    @staticmethod
    def target(batch: dict) -> torch.Tensor:
        return torch.log1p(batch["reference"].clamp_min(0))

    def sample_iterations(self, rng) -> int:
        return 0

    def eval_iterations(self) -> int:
        return 0

    def architecture(self) -> dict:
        return {"inputs": list(self.inputs), "channels": list(self.channels), "slope": self.slope,
                "epsilon": self.epsilon}

    # --- the library's weights file (docs/methods/rae.md) -----------------------------------
    def tensors(self):
        """(name, tensor) in the file's order: encIn.l, encRec.l, decA.l, decB.l; weight then bias."""
        for group, mods in (("encIn", self.enc_in), ("encRec", self.enc_rec), ("decA", self.dec_a),
                            ("decB", self.dec_b)):
            for l, m in enumerate(mods):
                yield f"{group}.{l}.weight", m.weight
                yield f"{group}.{l}.bias", m.bias

    def export_weights(self, path: str, training: dict | None = None) -> None:
        tensors = []
        for name, t in self.tensors():
            a = t.detach().cpu().numpy().astype("<f4")
            tensors.append({"name": name, "shape": list(a.shape),
                            "data": base64.b64encode(a.tobytes()).decode("ascii")})
        doc = {
            "format": WEIGHTS_FORMAT,
            "version": WEIGHTS_VERSION,
            "model": "RAE, recurrent denoising autoencoder (Chaitanya et al. 2017; Higginson 2023, Sec. 2.1)",
            "colorTransform": "log1p",
            "normalSpace": "view",
            "upsampling": "bilinear",
            **self.architecture(),
            "parameters": self.parameter_count(),
            "tensorEncoding": "base64 of little-endian float32, C order; conv weights [out, in, 3, 3]",
            "tensors": tensors,
            "training": training or {},
        }
        with open(path, "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")

    @staticmethod
    def load_weights(path: str) -> "RAE":
        with open(path) as f:
            doc = json.load(f)
        if doc.get("format") != WEIGHTS_FORMAT or doc.get("version") != WEIGHTS_VERSION:
            raise ValueError(f"{path}: not a version-{WEIGHTS_VERSION} {WEIGHTS_FORMAT} file")
        m = RAE(doc["inputs"], doc["channels"], doc["slope"], doc["epsilon"])
        stored = {t["name"]: t for t in doc["tensors"]}
        with torch.no_grad():
            for name, p in m.tensors():
                t = stored[name]
                a = np.frombuffer(base64.b64decode(t["data"]), dtype="<f4").reshape(t["shape"])
                p.copy_(torch.from_numpy(a.copy()))
        return m
