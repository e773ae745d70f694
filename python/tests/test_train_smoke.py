"""Training smoke test: a few steps on the tiny committed data set lower the loss, and a
resumed run continues from its checkpoint (loss curve, checkpoint, weights file written)."""
import json
import os
import tempfile
import unittest

from rtdenoise_train import train
from rtdenoise_train.models.rae import RAE
from rtdenoise_train.models.tnnd import TNND

TINY = os.path.join(os.path.dirname(__file__), "data", "tiny")


class TrainSmokeTest(unittest.TestCase):
    def test_a_few_steps_lower_the_loss_and_resume(self):
        with tempfile.TemporaryDirectory() as out:
            common = ["--model", "tnnd", "--data", TINY, "--out", out, "--patch", "16", "--batch", "4",
                      "--lr", "0.01", "--val-every", "10", "--checkpoint-every", "10", "--val-patches", "2",
                      "--threads", "1"]
            self.assertEqual(train.main(common + ["--steps", "20"]), 0)
            with open(os.path.join(out, "loss.json")) as f:
                first = json.load(f)["history"]
            self.assertEqual(len(first["train"]), 20)
            self.assertEqual(train.main(common + ["--steps", "40", "--resume"]), 0)
            with open(os.path.join(out, "loss.json")) as f:
                history = json.load(f)["history"]
            self.assertEqual([s for s, _ in history["train"]], list(range(1, 41)))
            self.assertEqual(history["train"][:20], first["train"], "resume kept the first 20 steps")
            val = [v for _, v in history["val"]]
            self.assertLess(val[-1], val[0], f"validation loss did not fall: {val}")
            self.assertTrue(os.path.getsize(os.path.join(out, "loss.png")) > 0)
            m = TNND.load_weights(os.path.join(out, "weights.json"))  # the library's format
            self.assertEqual(m.parameter_count(), 360)

    def test_rae_trains_on_clips_with_its_default_losses(self):
        # The RAE's defaults (L1 + L_g + L_t) on 2-frame clips of the tiny set; a few seconds.
        with tempfile.TemporaryDirectory() as out:
            args = ["--model", "rae", "--data", TINY, "--out", out, "--patch", "16", "--batch", "2", "--clip", "2",
                    "--lr", "0.005", "--steps", "16", "--val-every", "8", "--checkpoint-every", "8",
                    "--val-patches", "2", "--threads", "1"]
            self.assertEqual(train.main(args), 0)
            with open(os.path.join(out, "loss.json")) as f:
                doc = json.load(f)
            self.assertEqual(doc["losses"], {"mse": 0.0, "l1": 0.8, "gradient": 0.1, "temporal": 0.1, "ffl": 0.0})
            self.assertEqual(set(doc["history"]["terms"][0][2]), {"l1", "gradient", "temporal"})
            val = [v for _, v in doc["history"]["val"]]
            self.assertLess(val[-1], val[0], f"validation loss did not fall: {val}")
            m = RAE.load_weights(os.path.join(out, "weights.json"))
            self.assertEqual(m.parameter_count(), 80831)


if __name__ == "__main__":
    unittest.main()
