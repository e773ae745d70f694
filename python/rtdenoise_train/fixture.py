"""Writes the library's TNND cross-check fixture (src/methods/tnnd/testdata/): a small frame,
a weights file and the PyTorch model's output for it, computed in double precision.

    /usr/bin/python3 -m rtdenoise_train.fixture src/methods/tnnd/testdata

The C++ tests (src/methods/tnnd/tnnd_test.cpp, tests/vulkan/tnnd_vulkan_test.cpp) feed the frame
to the library's CPU and Vulkan `tnnd` and compare with `expected`: the expected values come
from this independent implementation, never from the code under test. The weights are random
(larger than trained ones, so every term of the rule matters) and fixed by the seed.
"""
from __future__ import annotations

import json
import math
import os
import sys

import numpy as np
import torch

from .models.tnnd import TNND, decode, encode

WIDTH, HEIGHT, ITERATIONS, SEED = 19, 13, 5, 7


def rotation(yaw: float, pitch: float) -> np.ndarray:
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rx = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    return rx @ ry


def make(out_dir: str) -> None:
    rng = np.random.default_rng(SEED)
    h, w = HEIGHT, WIDTH
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float64)
    # HDR colour: smooth structure, an edge and noise; a few values above 1.
    color = np.stack([0.4 + 0.3 * np.sin(xx / 3.0), 0.2 + 0.02 * xx * yy / 4, 0.3 * (xx > 9)])
    color = color * rng.exponential(1.0, size=(3, h, w)) + (rng.random((3, h, w)) < 0.03) * 4.0
    normal = rng.normal(size=(3, h, w))
    normal /= np.linalg.norm(normal, axis=0, keepdims=True)
    albedo = rng.uniform(0.05, 0.95, size=(3, h, w))
    world_to_camera = np.eye(4)
    world_to_camera[:3, :3] = rotation(0.6, -0.3)
    world_to_camera[:3, 3] = [0.5, -1.0, -3.0]

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
    planar = lambda a: [float(v) for v in np.asarray(a).reshape(-1)]
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


if __name__ == "__main__":
    make(sys.argv[1] if len(sys.argv) > 1 else "src/methods/tnnd/testdata")
