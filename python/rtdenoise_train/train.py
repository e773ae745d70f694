"""Train a model on an `rtdenoise dataset` directory (docs/training.md).

    /usr/bin/python3 -m rtdenoise_train.train --model tnnd --data DATA --out RUN [--steps N] [--resume]

Writes into RUN: checkpoint.pt (model, optimizer, step, random states, loss history; every
--checkpoint-every steps and at the end), loss.json and loss.png (training loss per step,
validation loss every --val-every steps), weights.json (the library's weights file) and
command.txt (the exact command). --resume continues from RUN/checkpoint.pt to --steps.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import shlex
import sys
import time

import numpy as np
import torch

from . import models
from .data import Dataset, PatchSampler, split_patches
from .losses import LossWeights, total_loss


def to_torch(batch: dict) -> dict:
    return {k: torch.from_numpy(v) for k, v in batch.items()}


def machine() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return f"{line.split(':', 1)[1].strip()}, torch threads {torch.get_num_threads()}"
    except OSError:
        pass
    return platform.processor() or platform.machine()


def plot(history: dict, path: str, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
    if history["train"]:
        s, v = zip(*history["train"])
        # A running mean over 20 steps: single steps differ by their random iteration counts.
        k = min(20, len(v))
        smooth = np.convolve(v, np.ones(k) / k, mode="valid")
        ax.plot(s, v, color="0.8", lw=0.6, label="train (per step)")
        ax.plot(s[k - 1:], smooth, color="C0", label=f"train (mean of {k})")
    if history["val"]:
        s, v = zip(*history["val"])
        ax.plot(s, v, "o-", color="C1", label="validation")
    ax.set_yscale("log")
    ax.set_xlabel("step")
    ax.set_ylabel("loss")
    ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def evaluate(model, batch, weights: LossWeights) -> float:
    with torch.no_grad():
        pred = model.predict(batch, model.eval_iterations())
        loss, _ = total_loss(pred, model.target(batch), weights)
    return float(loss)


def train(args) -> dict:
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    os.makedirs(args.out, exist_ok=True)
    model = models.create(args.model)
    if args.losses is None:
        args.losses = model.default_losses
    if args.clip is None:
        args.clip = model.default_clip
    weights = LossWeights.parse(args.losses)
    ds = Dataset(args.data, "train")
    train_ids, val_ids = split_patches(ds.patches(args.patch), args.val_fraction, args.seed)
    sampler = PatchSampler(ds, train_ids, args.patch, args.clip, augment=not args.no_augment, seed=args.seed)
    val_batch = to_torch(PatchSampler(ds, val_ids, args.patch, args.clip, augment=False).fixed(args.val_patches))
    opt = torch.optim.Adam(model.parameters(), lr=args.lr)
    rng = np.random.default_rng(args.seed + 1)
    history = {"train": [], "val": [], "terms": []}
    step, seconds = 0, 0.0
    ckpt_path = os.path.join(args.out, "checkpoint.pt")
    if args.resume and os.path.exists(ckpt_path):
        ckpt = torch.load(ckpt_path)
        model.load_state_dict(ckpt["model"])
        opt.load_state_dict(ckpt["optimizer"])
        step, history, seconds = ckpt["step"], ckpt["history"], ckpt["seconds"]
        sampler.rng.bit_generator.state = ckpt["sampler_rng"]
        rng.bit_generator.state = ckpt["rng"]
        torch.set_rng_state(ckpt["torch_rng"])
        print(f"resumed from {ckpt_path} at step {step}", file=sys.stderr)
    with open(os.path.join(args.out, "command.txt"), "w") as f:
        f.write(" ".join(shlex.quote(a) for a in [sys.executable, "-m", "rtdenoise_train.train"] + args.argv) + "\n")

    def save():
        torch.save({"model": model.state_dict(), "optimizer": opt.state_dict(), "step": step, "history": history,
                    "seconds": seconds, "sampler_rng": sampler.rng.bit_generator.state, "rng": rng.bit_generator.state,
                    "torch_rng": torch.get_rng_state(), "args": vars(args)}, ckpt_path + ".tmp")
        os.replace(ckpt_path + ".tmp", ckpt_path)
        with open(os.path.join(args.out, "loss.json"), "w") as f:
            json.dump({"model": args.model, "losses": vars(weights), "history": history, "seconds": seconds}, f)
        terms = ", ".join(f"{k}={v:g}" for k, v in vars(weights).items() if v)
        plot(history, os.path.join(args.out, "loss.png"), f"{args.model} ({terms})")

    if step == 0:
        history["val"].append([0, evaluate(model, val_batch, weights)])
    last = started = time.time()
    while step < args.steps:
        if args.time_limit and time.time() - started > 60 * args.time_limit:
            print(f"time limit of {args.time_limit:g} min reached at step {step}", file=sys.stderr)
            break
        batch = to_torch(sampler.sample(args.batch))
        iterations = model.sample_iterations(rng)
        pred = model.predict(batch, iterations)
        loss, terms = total_loss(pred, model.target(batch), weights)
        opt.zero_grad()
        loss.backward()
        if args.clip_grad > 0:
            torch.nn.utils.clip_grad_norm_(model.parameters(), args.clip_grad)
        opt.step()
        step += 1
        now = time.time()
        seconds += now - last
        last = now
        history["train"].append([step, float(loss)])
        history["terms"].append([step, iterations, terms])
        if step % args.val_every == 0 or step == args.steps:
            history["val"].append([step, evaluate(model, val_batch, weights)])
            print(f"step {step}/{args.steps}  train {float(loss):.5f}  val {history['val'][-1][1]:.5f}  "
                  f"({seconds:.0f} s)", file=sys.stderr, flush=True)
            last = time.time()
        if step % args.checkpoint_every == 0 or step == args.steps:
            save()
            last = time.time()
    if history["val"][-1][0] != step:  # stopped by --time-limit between validations
        history["val"].append([step, evaluate(model, val_batch, weights)])
    save()
    info = {"command": open(os.path.join(args.out, "command.txt")).read().strip(), "steps": step,
            "seconds": round(seconds, 1), "machine": machine(),
            "dataset": {"dir": args.data, "seed": ds.index["seed"], "size": ds.index["size"],
                        "referenceSpp": ds.index["reference"]["spp"],
                        "sequences": [s.name for s in ds.sequences]},
            "patches": {"train": len(train_ids), "validation": len(val_ids), "size": args.patch},
            "losses": vars(weights), "finalValidationLoss": history["val"][-1][1] if history["val"] else None,
            "torch": torch.__version__}
    model.export_weights(os.path.join(args.out, "weights.json"), info)
    return info


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="rtdenoise_train.train", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--model", default="tnnd", choices=sorted(models.MODELS))
    p.add_argument("--data", required=True, help="`rtdenoise dataset` output directory")
    p.add_argument("--out", required=True, help="run directory (checkpoint, loss curve, weights)")
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--batch", type=int, default=8)
    p.add_argument("--patch", type=int, default=128, help="patch side in pixels")
    p.add_argument("--clip", type=int, default=None,
                   help="consecutive frames per sample (>= 2 for the temporal loss; default: the model's, tnnd 1, rae 4)")
    p.add_argument("--lr", type=float, default=2e-3)
    p.add_argument("--clip-grad", type=float, default=1.0, help="gradient-norm clip (0: off)")
    p.add_argument("--losses", default=None, help="weights, e.g. mse=1,l1=0,gradient=0.5,temporal=0,ffl=0 (default: the "
                   "model's, tnnd mse=1,gradient=0.5, rae mse=0,l1=0.8,gradient=0.1,temporal=0.1)")
    p.add_argument("--val-fraction", type=float, default=0.2)
    p.add_argument("--val-patches", type=int, default=16, help="validation patches evaluated")
    p.add_argument("--val-every", type=int, default=50)
    p.add_argument("--checkpoint-every", type=int, default=100)
    p.add_argument("--no-augment", action="store_true", help="no mirroring")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--threads", type=int, default=2, help="torch threads (the machine is shared: at most 2)")
    p.add_argument("--resume", action="store_true", help="continue from <out>/checkpoint.pt")
    p.add_argument("--time-limit", type=float, default=0,
                   help="stop (checkpoint, weights) after this many minutes of this invocation (0: none)")
    return p


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = parser().parse_args(argv)
    args.argv = argv
    if args.threads > 2:
        print("note: --threads > 2 on a shared machine", file=sys.stderr)
    info = train(args)
    print(json.dumps(info, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
