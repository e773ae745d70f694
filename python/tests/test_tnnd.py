"""TNND (checklist 30-32): 39 perception channels, Sobel/Laplace of a ramp, 360 parameters,
the fused convolution equals the perception form, finite output for 1..K iterations, stable
quality across the trained iteration range with the committed weights, and the committed C++
fixture is what this model computes."""
import json
import os
import tempfile
import unittest

import numpy as np
import torch

from rtdenoise_train import fixture
from rtdenoise_train.data import Dataset, PatchSampler, split_patches
from rtdenoise_train.models.tnnd import PERCEPTION, TNND, perceive

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
TINY = os.path.join(os.path.dirname(__file__), "data", "tiny")
WEIGHTS = os.path.join(ROOT, "src", "methods", "tnnd", "tnnd_weights.json")


def ramp(h=7, w=9):
    yy, xx = torch.meshgrid(torch.arange(h, dtype=torch.float64), torch.arange(w, dtype=torch.float64), indexing="ij")
    return torch.stack([0.1 * (c + 1) * xx - 0.05 * c * yy + c for c in range(9)])[None]


class TnndTest(unittest.TestCase):
    def test_perception_shape_and_ramp(self):
        s = ramp()
        p = perceive(s)
        self.assertEqual(p.shape[1], PERCEPTION)
        self.assertEqual(PERCEPTION, 39)
        inner = p[0, :, 1:-1, 1:-1]
        for c in range(9):
            torch.testing.assert_close(inner[c], s[0, c, 1:-1, 1:-1])                       # state
            if c < 3:
                torch.testing.assert_close(inner[9 + c], s[0, c, 1:-1, 1:-1])               # Gaussian
            torch.testing.assert_close(inner[12 + c], torch.zeros_like(inner[0]), atol=1e-12, rtol=0)  # Laplace
            torch.testing.assert_close(inner[21 + c], torch.full_like(inner[0], 0.1 * (c + 1)))        # Sobel x
            torch.testing.assert_close(inner[30 + c], torch.full_like(inner[0], -0.05 * c))            # Sobel y

    def test_parameter_count(self):
        self.assertEqual(TNND().parameter_count(), 360)  # 39 x 9 + 9 (the thesis: 351 without bias)

    def test_fused_step_equals_perception_form(self):
        m = TNND().double()
        with torch.no_grad():
            m.W.normal_(0, 0.4)
        s = torch.rand(2, 9, 11, 13, dtype=torch.float64)
        torch.testing.assert_close(m.step(s), m.step_by_perception(s), atol=1e-12, rtol=0)

    def test_finite_after_1_to_k_iterations(self):
        m = TNND.load_weights(WEIGHTS)
        ds = Dataset(TINY)
        batch = PatchSampler(ds, ds.patches(16), 16, augment=False).fixed(4)
        state = None
        with torch.no_grad():
            for k in range(1, 49):
                pred = m.predict({key: torch.from_numpy(v) for key, v in batch.items()}, k)
                self.assertTrue(torch.isfinite(pred).all(), f"{k} iterations")

    def test_quality_is_stable_across_the_trained_iteration_range(self):
        # The committed weights on the tiny data set (other scenes than the training ones): the
        # MSE (log space) at every count in the training range stays within 35% of the default
        # count's and below 75% of the input's. (On the training data set's patches the spread
        # is 25%; beyond the range the automaton drifts: docs/methods/tnnd.md.)
        m = TNND.load_weights(WEIGHTS)
        ds = Dataset(TINY)
        b = {k: torch.from_numpy(v) for k, v in PatchSampler(ds, ds.patches(16), 16, augment=False).fixed(8).items()}
        target = TNND.target(b)
        with torch.no_grad():
            err = {k: float(((m.predict(b, k) - target) ** 2).mean()) for k in range(TNND.train_iterations[0],
                                                                                TNND.train_iterations[1] + 1)}
            noisy = float(((m.predict(b, 0) - target) ** 2).mean())
        ref = err[TNND.default_iterations]
        for k, e in err.items():
            self.assertLess(e, 0.75 * noisy, f"{k} iterations: {e}, hardly better than the noisy input's {noisy}")
            self.assertLess(abs(e - ref), 0.35 * ref, f"{k} iterations: {e} vs {ref} at {TNND.default_iterations}")

    def test_committed_fixture_is_this_model(self):
        with tempfile.TemporaryDirectory() as d:
            fixture.make(d)
            ours = json.load(open(os.path.join(d, "tnnd_fixture.json")))
        committed = json.load(open(os.path.join(ROOT, "src", "methods", "tnnd", "testdata", "tnnd_fixture.json")))
        np.testing.assert_allclose(ours["expected"], committed["expected"], rtol=1e-9)


if __name__ == "__main__":
    unittest.main()
