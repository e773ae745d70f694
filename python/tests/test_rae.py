"""The RAE (models/rae.py): checklist item 27 (any input size, the recurrence), the weights
file round trip, the committed C++ fixture is this model's output, and the committed weights
load as the documented architecture."""
import json
import os
import tempfile
import unittest

import numpy as np
import torch

from rtdenoise_train import fixture
from rtdenoise_train.models.rae import INPUT_SETS, RAE

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def frame(seed: int, h: int, w: int):
    g = torch.Generator().manual_seed(seed)
    color = torch.rand(1, 3, h, w, generator=g) * 2
    albedo = torch.rand(1, 3, h, w, generator=g)
    normal = torch.nn.functional.normalize(torch.randn(1, 3, h, w, generator=g), dim=1)
    return color, albedo, normal


class RaeTest(unittest.TestCase):
    def test_any_input_size(self):
        m = RAE()
        self.assertEqual(m.multiple, 8)
        for h, w in [(1, 1), (5, 7), (8, 8), (13, 21), (16, 9)]:
            with torch.no_grad():
                r, hidden = m(*frame(0, h, w))
            self.assertEqual(tuple(r.shape), (1, 3, h, w))
            self.assertTrue(torch.isfinite(r).all())
            self.assertTrue((r >= 0).all())
            # The hidden states are those of the padded frame: ceil(size / 8) * 8 / 2^l.
            self.assertEqual(tuple(hidden[0].shape[-2:]), (-(-h // 8) * 8, -(-w // 8) * 8))

    def test_hidden_state_changes_the_output_and_none_is_a_first_frame(self):
        m = RAE()
        x = frame(1, 16, 24)
        with torch.no_grad():
            first, hidden = m(*x)
            second, _ = m(*x, hidden=hidden)
            again, _ = m(*x, hidden=None)
        self.assertGreater(float((first - second).abs().max()), 1e-4)
        self.assertTrue(torch.equal(first, again))

    def test_sequence_carries_the_state(self):
        m = RAE()
        x = frame(2, 8, 8)
        batch = {"color": torch.stack([x[0]] * 3, 1), "albedo": torch.stack([x[1]] * 3, 1),
                 "normal": torch.stack([x[2]] * 3, 1)}
        with torch.no_grad():
            seq = m.sequence(batch)
            alone, _ = m(*x)
        self.assertTrue(torch.allclose(seq[:, 0], alone))
        self.assertGreater(float((seq[:, 1] - seq[:, 0]).abs().max()), 1e-4)

    def test_input_sets_and_their_channels(self):
        for name, inputs in INPUT_SETS.items():
            m = RAE(name)
            self.assertEqual(m.inputs, inputs)
            self.assertEqual(m.enc_in[0].in_channels, 3 * len(inputs))
        with self.assertRaises(ValueError):
            RAE(("color", "normal"))

    def test_weights_file_round_trip(self):
        m = RAE("color+albedo", (4, 6, 8), seed=3)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "w.json")
            m.export_weights(path)
            n = RAE.load_weights(path)
        self.assertEqual((n.inputs, n.channels), (m.inputs, m.channels))
        for (a, p), (b, q) in zip(m.tensors(), n.tensors()):
            self.assertEqual(a, b)
            self.assertTrue(torch.equal(p, q))

    def test_committed_fixture_is_this_model(self):
        with tempfile.TemporaryDirectory() as d:
            fixture.make_rae(d)
            for name in fixture.RAE_INPUT_SETS:
                f = f"rae_fixture_{name.replace('+', '_')}.json"
                ours = json.load(open(os.path.join(d, f)))
                committed = json.load(open(os.path.join(ROOT, "src", "methods", "rae", "testdata", f)))
                np.testing.assert_allclose(ours["expected"], committed["expected"], rtol=1e-9, atol=1e-12)

    def test_committed_weights_are_the_documented_model(self):
        m = RAE.load_weights(os.path.join(ROOT, "src", "methods", "rae", "rae_weights.json"))
        self.assertEqual(m.channels, RAE.default_channels)
        self.assertEqual(m.inputs, INPUT_SETS["color+albedo+normal"])
        self.assertEqual(m.parameter_count(), 80831)


if __name__ == "__main__":
    unittest.main()
