"""Runs the training pipeline's tests (ctest `python_train`): exit 77 (skipped) where PyTorch
is not installed, else unittest's status. CI installs python3-torch, so there they run."""
import os
import sys
import unittest

try:
    import torch  # noqa: F401
    import numpy  # noqa: F401
    import matplotlib  # noqa: F401
except ImportError as e:
    print(f"skipped: {e}")
    sys.exit(77)

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))
suite = unittest.defaultTestLoader.discover(here, top_level_dir=os.path.dirname(here))
result = unittest.TextTestRunner(verbosity=2).run(suite)
sys.exit(0 if result.wasSuccessful() else 1)
