#!/usr/bin/python3
"""What fp16 storage of the RAE's activations would cost in quality (docs/methods/rae.md).

Runs the committed weights (src/methods/rae/rae_weights.json) over the held-out test sequences
of the data set in float32, and again with every stored activation rounded to float16 (each
convolution's input and output: the network input, pooled and upsampled tensors, the features
and the hidden states; the arithmetic stays float32, as fp16 storage on a GPU would do), and
prints per sequence the PSNR of each against the reference and of the fp16 output against the
float32 one, on Reinhard-tone-mapped, gamma-2.2 radiance in [0, 1]:

    PYTHONPATH=python /usr/bin/python3 tools/eval/rae_fp16.py build/data/tnnd-v1
"""
import sys

import numpy as np
import torch

from rtdenoise_train.data import Dataset, PatchId, clip
from rtdenoise_train.models.rae import RAE


def display(x: torch.Tensor) -> torch.Tensor:
    x = x.clamp_min(0)
    return (x / (1 + x)) ** (1 / 2.2)


def psnr(a: torch.Tensor, b: torch.Tensor) -> float:
    mse = float(((a - b) ** 2).mean())
    return float("inf") if mse == 0 else 10 * np.log10(1 / mse)


def half_storage(model: RAE):
    """Rounds every convolution's input and output to float16 (hooks; remove() to undo)."""
    r = lambda t: t.half().float()
    handles = []
    for m in model.modules():
        if isinstance(m, torch.nn.Conv2d):
            handles.append(m.register_forward_pre_hook(lambda _m, args: tuple(r(a) for a in args)))
            handles.append(m.register_forward_hook(lambda _m, _args, out: r(out)))
    return handles


def main(root: str) -> None:
    torch.set_num_threads(1)
    model = RAE.load_weights("src/methods/rae/rae_weights.json").eval()
    ds = Dataset(root, "test")
    print(f"{'sequence':24} {'fp32 vs ref':>12} {'fp16 vs ref':>12} {'fp16 vs fp32':>13}  (PSNR dB, all frames)")
    for i, s in enumerate(ds.sequences):
        c = clip(ds, PatchId(i, 0, 0), min(s.height, s.width), 0, s.frames)
        batch = {k: torch.from_numpy(v)[None] for k, v in c.items()}
        with torch.no_grad():
            full = model.sequence(batch)
            handles = half_storage(model)
            half = model.sequence(batch)
            for h in handles:
                h.remove()
        ref = display(batch["reference"])
        print(f"{s.name:24} {psnr(display(full), ref):12.2f} {psnr(display(half), ref):12.2f} "
              f"{psnr(display(half), display(full)):13.1f}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "build/data/tnnd-v1")
