"""The thesis's losses (checklist 28): zero for a perfect prediction, L_t blind to a constant
offset over time, L_g sensitive to blur, FFL weights hard frequencies."""
import unittest

import torch

from rtdenoise_train import losses
from rtdenoise_train.losses import LossWeights, total_loss


class LossTest(unittest.TestCase):
    def setUp(self):
        g = torch.Generator().manual_seed(0)
        self.t = torch.rand(2, 3, 3, 32, 32, generator=g)  # [B, T, C, H, W]

    def test_zero_when_equal(self):
        w = LossWeights(mse=1, l1=1, gradient=1, temporal=1, ffl=1)
        loss, terms = total_loss(self.t, self.t, w)
        self.assertEqual(float(loss), 0.0)
        self.assertEqual(set(terms), {"mse", "l1", "gradient", "temporal", "ffl"})

    def test_temporal_ignores_a_constant_offset(self):
        self.assertAlmostEqual(float(losses.temporal(self.t + 0.3, self.t)), 0.0, places=6)
        flicker = self.t.clone()
        flicker[:, 1] += 0.3
        self.assertGreater(float(losses.temporal(flicker, self.t)), 0.1)

    def test_gradient_loss_prefers_edges(self):
        t = torch.zeros(1, 1, 32, 32)
        t[..., 16:] = 1.0  # a step edge
        blurred = losses.blur3x3(losses.blur3x3(t))
        self.assertGreater(float(losses.gradient(blurred, t)), 0)
        self.assertEqual(float(losses.gradient(t, t)), 0)
        # A prediction with the same MSE as the blurred one, but the edge kept (an offset).
        offset = t + float(losses.mse(blurred, t)) ** 0.5
        self.assertAlmostEqual(float(losses.mse(offset, t)), float(losses.mse(blurred, t)), places=6)
        self.assertLess(float(losses.gradient(offset, t)), float(losses.gradient(blurred, t)))

    def test_focal_frequency_positive_and_weighted(self):
        p = self.t[:, 0] + 0.1 * torch.sin(torch.arange(32.0))  # an error at one frequency
        self.assertGreater(float(losses.focal_frequency(p, self.t[:, 0])), 0)

    def test_parse_weights(self):
        w = LossWeights.parse("mse=0.5,ffl=0.1")
        self.assertEqual((w.mse, w.ffl, w.gradient), (0.5, 0.1, 0.5))
        with self.assertRaises(ValueError):
            LossWeights.parse("ssim=1")


if __name__ == "__main__":
    unittest.main()
