"""The data set of `rtdenoise dataset` (docs/dataset.md), read through its training cache.

The cache is written by the library's side of the project: `rtdenoise dataset` renders each
sequence, reads it back with rtd::SequenceReader and stores the buffers as
``<sequence>/cache.npy`` (float16, [frames, 18, H, W]; channel names in dataset.json) and the
cameras as ``<sequence>/cameras.npy`` (float32, [frames, 2, 4, 4]). This module has no image
reader of its own: it maps those arrays with numpy.

Samples are *patches*: a patch is one 128x128 tile of one sequence, on a grid of non-overlapping
tiles, holding every frame of the sequence (a spatio-temporal tube). The 80/20 train/validation
split shuffles patch ids, so no pixel of a patch is ever in both splits. A training sample is a
clip of `clip` consecutive frames of one patch, optionally mirrored.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass

import numpy as np

# Channels of cache.npy (dataset.json "cache.channels" lists them; checked on load).
CACHE_CHANNELS = [
    "color.R", "color.G", "color.B", "albedo.R", "albedo.G", "albedo.B",
    "normal.X", "normal.Y", "normal.Z", "depth.Z", "motion.X", "motion.Y",
    "emission.R", "emission.G", "emission.B", "reference.R", "reference.G", "reference.B",
]
COLOR, ALBEDO, NORMAL, DEPTH, MOTION, EMISSION, REFERENCE = (
    slice(0, 3), slice(3, 6), slice(6, 9), slice(9, 10), slice(10, 12), slice(12, 15), slice(15, 18))


@dataclass(frozen=True)
class PatchId:
    """One tile of one sequence: (sequence index, tile row, tile column)."""
    sequence: int
    ty: int
    tx: int


class Sequence:
    """One sequence of the data set: its cache (memory-mapped) and cameras."""

    def __init__(self, root: str, entry: dict):
        self.name = entry["name"]
        self.split = entry["split"]
        self.dir = os.path.join(root, entry["dir"])
        self.cache = np.load(os.path.join(self.dir, "cache.npy"), mmap_mode="r")
        self.cameras = np.load(os.path.join(self.dir, "cameras.npy"))
        if self.cache.ndim != 4 or self.cache.shape[1] != len(CACHE_CHANNELS):
            raise ValueError(f"{self.dir}/cache.npy: shape {self.cache.shape}, expected [frames, "
                             f"{len(CACHE_CHANNELS)}, H, W]")
        if self.cameras.shape != (self.cache.shape[0], 2, 4, 4):
            raise ValueError(f"{self.dir}/cameras.npy: shape {self.cameras.shape} does not match the cache")
        self.frames, _, self.height, self.width = self.cache.shape


class Dataset:
    """The sequences of one split ("train" or "test") of a data set directory."""

    def __init__(self, root: str, split: str = "train"):
        with open(os.path.join(root, "dataset.json")) as f:
            index = json.load(f)
        if index.get("generator") != "rtdenoise dataset" or index.get("version") != 1:
            raise ValueError(f"{root}/dataset.json: not a version-1 `rtdenoise dataset` index")
        if index["cache"]["channels"] != CACHE_CHANNELS:
            raise ValueError(f"{root}/dataset.json: cache channels {index['cache']['channels']} differ from "
                             f"the layout this loader knows")
        self.root = root
        self.index = index
        self.sequences = [Sequence(root, e) for e in index["sequences"] if e["split"] == split]
        if not self.sequences:
            raise ValueError(f"{root}: no sequences in split '{split}'")

    def patches(self, size: int) -> list[PatchId]:
        """Every non-overlapping size x size tile of every sequence (tiles that fit entirely)."""
        out = []
        for i, s in enumerate(self.sequences):
            for ty in range(s.height // size):
                for tx in range(s.width // size):
                    out.append(PatchId(i, ty, tx))
        if not out:
            raise ValueError(f"{self.root}: no sequence is at least {size}x{size}")
        return out


def split_patches(patches: list[PatchId], validation: float = 0.2, seed: int = 0):
    """Shuffles the patch ids and splits them (1 - validation) / validation: disjoint by id,
    and ids are non-overlapping tiles, so no pixel of a sequence is in both splits."""
    order = np.random.default_rng(seed).permutation(len(patches))
    n_val = max(1, int(round(validation * len(patches)))) if len(patches) > 1 else 0
    val = [patches[i] for i in order[:n_val]]
    train = [patches[i] for i in order[n_val:]]
    return train, val


def view_space_normals(normal: np.ndarray, world_to_camera: np.ndarray) -> np.ndarray:
    """World-space normals [..., 3, H, W] -> camera space (x right, y up, z towards the viewer)
    with the rotation part of the row-major worldToCamera matrix [..., 4, 4]."""
    r = world_to_camera[..., :3, :3]
    return np.einsum("...ij,...jhw->...ihw", r, normal)


def clip(ds: Dataset, patch: PatchId, size: int, start: int, length: int) -> dict:
    """The buffers of frames [start, start + length) of a patch as float32 arrays [T, C, size, size]:
    color and reference with the emission taken out (as the library's import does: denoisers
    filter color - emission and add the emission back), view-space normals, albedo, depth,
    motion, emission."""
    s = ds.sequences[patch.sequence]
    y0, x0 = patch.ty * size, patch.tx * size
    raw = np.asarray(s.cache[start:start + length, :, y0:y0 + size, x0:x0 + size], dtype=np.float32)
    emission = raw[:, EMISSION]
    return {
        "color": np.maximum(raw[:, COLOR] - emission, 0.0),
        "albedo": raw[:, ALBEDO],
        "normal": view_space_normals(raw[:, NORMAL], s.cameras[start:start + length, 0]).astype(np.float32),
        "depth": raw[:, DEPTH],
        "motion": raw[:, MOTION],
        "emission": emission,
        "reference": np.maximum(raw[:, REFERENCE] - emission, 0.0),
    }


def mirror(sample: dict, horizontal: bool, vertical: bool) -> dict:
    """Mirrors every buffer of a sample (arrays [..., C, H, W]); the view-space normal's x (or y)
    component and the motion's x (or y) change sign with the image, so the mirrored sample is
    the view of the mirrored scene."""
    out = {}
    for k, v in sample.items():
        if horizontal:
            v = v[..., ::-1]
        if vertical:
            v = v[..., ::-1, :]
        v = np.ascontiguousarray(v)
        if k in ("normal", "motion"):
            v = v.copy()
            if horizontal:
                v[..., 0, :, :] *= -1
            if vertical:
                v[..., 1, :, :] *= -1
        out[k] = v
    return out


class PatchSampler:
    """Random clips of patches with random mirroring, as batches of float32 arrays [B, T, C, H, W]."""

    def __init__(self, ds: Dataset, patches: list[PatchId], size: int, clip_length: int = 1,
                 augment: bool = True, seed: int = 0):
        self.ds, self.patches, self.size, self.clip_length, self.augment = ds, patches, size, clip_length, augment
        self.rng = np.random.default_rng(seed)
        for p in patches:
            if ds.sequences[p.sequence].frames < clip_length:
                raise ValueError(f"sequence {ds.sequences[p.sequence].name} has fewer than {clip_length} frames")

    def sample(self, batch: int) -> dict:
        items = []
        for _ in range(batch):
            p = self.patches[self.rng.integers(len(self.patches))]
            frames = self.ds.sequences[p.sequence].frames
            start = int(self.rng.integers(frames - self.clip_length + 1))
            s = clip(self.ds, p, self.size, start, self.clip_length)
            if self.augment:
                s = mirror(s, bool(self.rng.integers(2)), bool(self.rng.integers(2)))
            items.append(s)
        return {k: np.stack([it[k] for it in items]) for k in items[0]}

    def fixed(self, count: int, start: int = 0) -> dict:
        """A deterministic batch: the first `count` patches' clips from frame `start` (validation)."""
        items = [clip(self.ds, p, self.size, min(start, self.ds.sequences[p.sequence].frames - self.clip_length),
                      self.clip_length) for p in self.patches[:count]]
        return {k: np.stack([it[k] for it in items]) for k in items[0]}
