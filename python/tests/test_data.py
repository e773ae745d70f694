"""Data set pipeline (checklist 29): the 80/20 patch split is disjoint, mirroring flips the
normal's and the motion's component, the cache reads back as rtdenoise dataset wrote it."""
import os
import unittest

import numpy as np

from rtdenoise_train.data import Dataset, PatchSampler, clip, mirror, split_patches, view_space_normals

TINY = os.path.join(os.path.dirname(__file__), "data", "tiny")


class DataTest(unittest.TestCase):
    def setUp(self):
        self.ds = Dataset(TINY, "train")

    def test_cache_layout(self):
        self.assertEqual(len(self.ds.sequences), 2)
        s = self.ds.sequences[0]
        self.assertEqual((s.frames, s.height, s.width), (2, 32, 32))
        n = np.asarray(s.cache[0, 6:9], dtype=np.float32)
        length = np.linalg.norm(n, axis=0)
        hit = length > 0  # sky pixels have no normal
        self.assertTrue(np.all(np.abs(length[hit] - 1) < 2e-3), "normals are unit vectors (float16)")

    def test_split_is_disjoint_and_complete(self):
        patches = self.ds.patches(16)
        self.assertEqual(len(patches), 2 * 4)  # 2 sequences x (32/16)^2 tiles
        train, val = split_patches(patches, 0.2, seed=5)
        self.assertEqual(len(set(train) & set(val)), 0)
        self.assertEqual(set(train) | set(val), set(patches))
        self.assertEqual(len(val), round(0.2 * len(patches)))
        # Tiles do not overlap: no pixel of a sequence in two patches.
        for a in patches:
            for b in patches:
                if a != b and a.sequence == b.sequence:
                    self.assertNotEqual((a.ty, a.tx), (b.ty, b.tx))

    def test_mirror_flips_the_normal_and_motion_components(self):
        s = clip(self.ds, self.ds.patches(16)[0], 16, 0, 2)
        h = mirror(s, horizontal=True, vertical=False)
        np.testing.assert_array_equal(h["normal"][:, 0], -s["normal"][:, 0, :, ::-1])
        np.testing.assert_array_equal(h["normal"][:, 1:], s["normal"][:, 1:, :, ::-1])
        np.testing.assert_array_equal(h["motion"][:, 0], -s["motion"][:, 0, :, ::-1])
        np.testing.assert_array_equal(h["color"], s["color"][..., ::-1])
        v = mirror(s, horizontal=False, vertical=True)
        np.testing.assert_array_equal(v["normal"][:, 1], -s["normal"][:, 1, ::-1, :])
        np.testing.assert_array_equal(v["normal"][:, 2], s["normal"][:, 2, ::-1, :])
        np.testing.assert_array_equal(v["motion"][:, 1], -s["motion"][:, 1, ::-1, :])
        np.testing.assert_array_equal(mirror(h, True, False)["normal"], s["normal"])

    def test_view_space_normals(self):
        # worldToCamera's rotation rows (0,0,-1), (0,1,0), (1,0,0): world +x is camera +z.
        r = np.array([[0, 0, -1, 0], [0, 1, 0, 0], [1, 0, 0, 0], [0, 0, 0, 1]], dtype=np.float32)
        n = np.zeros((3, 1, 1), np.float32)
        n[0] = 1
        v = view_space_normals(n, r)
        np.testing.assert_allclose(v[:, 0, 0], [0, 0, 1])

    def test_sampler_shapes(self):
        train, _ = split_patches(self.ds.patches(16))
        b = PatchSampler(self.ds, train, 16, clip_length=2, seed=1).sample(3)
        self.assertEqual(b["color"].shape, (3, 2, 3, 16, 16))
        self.assertEqual(b["normal"].shape, (3, 2, 3, 16, 16))
        self.assertTrue(np.all(b["color"] >= 0) and np.all(b["reference"] >= 0))


if __name__ == "__main__":
    unittest.main()
