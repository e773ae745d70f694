"""Writes the library's cross-check fixtures of the learned methods: small frames, a weights
file and the PyTorch model's output for them, computed in double precision.

    /usr/bin/python3 -m rtdenoise_train.fixture tnnd src/methods/tnnd/testdata
    /usr/bin/python3 -m rtdenoise_train.fixture rae src/methods/rae/testdata

The C++ tests (src/methods/<m>/<m>_test.cpp, tests/vulkan/tnnd_vulkan_test.cpp) feed the frames
to the library's `tnnd` / `rae` and compare with `expected`: the expected values come from this
independent implementation, never from the code under test. The weights are random (TNND's
larger than trained ones, so every term of the rule matters) and fixed by the seed.
"""
from __future__ import annotations

import json
import math
import os
import sys

import numpy as np
import torch

from .models.rae import RAE
from .models.tnnd import TNND, decode, encode

WIDTH, HEIGHT, ITERATIONS, SEED = 19, 13, 5, 7


def rotation(yaw: float, pitch: float) -> np.ndarray:
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rx = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    return rx @ ry


def hdr_color(rng, h: int, w: int) -> np.ndarray:
    """HDR colour [3, h, w]: smooth structure, an edge and noise; a few values above 1."""
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float64)
    color = np.stack([0.4 + 0.3 * np.sin(xx / 3.0), 0.2 + 0.02 * xx * yy / 4, 0.3 * (xx > 9)])
    return color * rng.exponential(1.0, size=(3, h, w)) + (rng.random((3, h, w)) < 0.03) * 4.0


def features(rng, h: int, w: int):
    """(world-space unit normals, albedo in [0.05, 0.95], worldToCamera 4x4 of a rotated camera)."""
    normal = rng.normal(size=(3, h, w))
    normal /= np.linalg.norm(normal, axis=0, keepdims=True)
    albedo = rng.uniform(0.05, 0.95, size=(3, h, w))
    world_to_camera = np.eye(4)
    world_to_camera[:3, :3] = rotation(0.6, -0.3)
    world_to_camera[:3, 3] = [0.5, -1.0, -3.0]
    return normal, albedo, world_to_camera


def planar(a) -> list:
    return [float(v) for v in np.asarray(a).reshape(-1)]


def make(out_dir: str) -> None:
    """TNND's fixture: one 19x13 frame, 5 iterations."""
    rng = np.random.default_rng(SEED)
    h, w = HEIGHT, WIDTH
    color = hdr_color(rng, h, w)
    normal, albedo, world_to_camera = features(rng, h, w)

    model = TNND().double()
    with torch.no_grad():
        g = torch.Generator().manual_seed(SEED)
        model.W.copy_(torch.randn(39, 9, generator=g, dtype=torch.float64) * 0.4)
        model.b.copy_(-0.5 + 0.1 * torch.randn(9, generator=g, dtype=torch.float64))
    view_normal = np.einsum("ij,jhw->ihw", world_to_camera[:3, :3], normal)
    t = lambda a: torch.from_numpy(np.ascontiguousarray(a))[None]
    with torch.no_grad():
        state = model(encode(t(color), t(view_normal), t(albedo)), ITERATIONS)
        radiance = decode(state)[0].numpy()

    os.makedirs(out_dir, exist_ok=True)
    model.export_weights(os.path.join(out_dir, "tnnd_fixture_weights.json"),
                         {"note": "random weights of the cross-check fixture (rtdenoise_train.fixture)"})
    doc = {
        "comment": "TNND cross-check fixture written by python/rtdenoise_train/fixture.py (PyTorch, float64); "
                   "arrays are planar [channel][y][x]",
        "width": w, "height": h, "iterations": ITERATIONS, "weights": "tnnd_fixture_weights.json",
        "worldToCamera": planar(world_to_camera),
        "color": planar(color), "normal": planar(normal), "albedo": planar(albedo),
        "expectedState": planar(state[0].numpy()), "expected": planar(radiance),
    }
    with open(os.path.join(out_dir, "tnnd_fixture.json"), "w") as f:
        json.dump(doc, f)
        f.write("\n")


# RAE: a 3-level network (channels 6, 8, 10: every part of the architecture, small files) on
# frames of 21x13 (not multiples of 2^(L-1) = 4: the padding is exercised), three frames (the
# recurrence: frame 2 repeats frame 1's input) per input set.
RAE_WIDTH, RAE_HEIGHT, RAE_FRAMES, RAE_CHANNELS = 21, 13, 3, (6, 8, 10)
RAE_INPUT_SETS = ("color+albedo+normal", "color")


def make_rae(out_dir: str) -> None:
    """The RAE's fixtures: per input set a weights file and rae_fixture_<set>.json."""
    os.makedirs(out_dir, exist_ok=True)
    for k, inputs in enumerate(RAE_INPUT_SETS):
        rng = np.random.default_rng(SEED + k)
        h, w = RAE_HEIGHT, RAE_WIDTH
        colors = [hdr_color(rng, h, w), hdr_color(rng, h, w)]
        colors.append(colors[1])
        normal, albedo, world_to_camera = features(rng, h, w)
        model = RAE(inputs, RAE_CHANNELS, seed=SEED + k).double()
        with torch.no_grad():  # non-zero biases (PyTorch's initialisation has small ones)
            g = torch.Generator().manual_seed(SEED + k)
            for _, p in model.tensors():
                p.add_(0.05 * torch.randn(p.shape, generator=g, dtype=torch.float64))
        view_normal = np.einsum("ij,jhw->ihw", world_to_camera[:3, :3], normal)
        t = lambda a: torch.from_numpy(np.ascontiguousarray(a))[None]
        expected, hidden = [], None
        with torch.no_grad():
            for c in colors:
                r, hidden = model(t(c), t(albedo), t(view_normal), hidden)
                expected.append(r[0].numpy())
        name = inputs.replace("+", "_")
        model.export_weights(os.path.join(out_dir, f"rae_fixture_{name}_weights.json"),
                             {"note": "random weights of the cross-check fixture (rtdenoise_train.fixture)"})
        doc = {
            "comment": "RAE cross-check fixture written by python/rtdenoise_train/fixture.py (PyTorch, float64); "
                       "arrays are planar [channel][y][x], one per frame, the hidden state carried from frame to frame",
            "width": w, "height": h, "frames": len(colors), "inputs": inputs,
            "weights": f"rae_fixture_{name}_weights.json", "worldToCamera": planar(world_to_camera),
            "color": [planar(c) for c in colors], "normal": planar(normal), "albedo": planar(albedo),
            "expected": [planar(e) for e in expected],
        }
        with open(os.path.join(out_dir, f"rae_fixture_{name}.json"), "w") as f:
            json.dump(doc, f)
            f.write("\n")


if __name__ == "__main__":
    which = sys.argv[1] if len(sys.argv) > 1 else "tnnd"
    if which == "tnnd":
        make(sys.argv[2] if len(sys.argv) > 2 else "src/methods/tnnd/testdata")
    elif which == "rae":
        make_rae(sys.argv[2] if len(sys.argv) > 2 else "src/methods/rae/testdata")
    else:
        sys.exit(f"usage: python -m rtdenoise_train.fixture tnnd|rae [DIR]")
