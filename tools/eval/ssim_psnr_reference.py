#!/usr/bin/python3
"""Independent PSNR/SSIM values for tests/eval/metrics_test.cpp, from scikit-image.

Run once (Debian bookworm: apt-get install python3-skimage, scikit-image 0.19.3):
    /usr/bin/python3 tools/eval/ssim_psnr_reference.py
The test images are defined by integer formulas so that C++ and Python build them exactly.
"""
import numpy as np
import skimage
from skimage.metrics import peak_signal_noise_ratio, structural_similarity

M = 0xFFFFFFFF


def pair_a():  # 32x24 RGB pattern and a copy with a hashed perturbation of +-20/255
    h, w = 24, 32
    a = np.zeros((h, w, 3)); b = np.zeros((h, w, 3))
    for y in range(h):
        for x in range(w):
            for c in range(3):
                base = (x * 7 + y * 13 + c * 5 + (x * y) % 11) % 256
                hsh = (((x * 73856093) & M) ^ ((y * 19349663) & M) ^ ((c * 83492791) & M)) % 41 - 20
                a[y, x, c] = base / 255.0
                b[y, x, c] = min(max(base + hsh, 0), 255) / 255.0
    return a, b


def pair_b():  # 17x13 grey: two unrelated patterns
    h, w = 13, 17
    a = np.zeros((h, w)); b = np.zeros((h, w))
    for y in range(h):
        for x in range(w):
            a[y, x] = ((x * x + 3 * y) % 29) / 28.0
            b[y, x] = ((x + y * y) % 31) / 30.0
    return a, b


def pair_c():  # 40x36 RGB smooth gradient and a darker, shifted version
    h, w = 36, 40
    a = np.zeros((h, w, 3)); b = np.zeros((h, w, 3))
    for y in range(h):
        for x in range(w):
            for c in range(3):
                a[y, x, c] = ((x * 3 + y * 2 + c * 40) % 200) / 255.0
                b[y, x, c] = ((x * 3 + y * 2 + c * 40 + 6) % 200) * 0.8 / 255.0
    return a, b


def ssim(a, b):
    kw = dict(gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=1.0)
    if a.ndim == 3:
        kw["channel_axis"] = 2
    return structural_similarity(a, b, **kw)


print("scikit-image", skimage.__version__, "numpy", np.__version__)
for name, (a, b) in [("A", pair_a()), ("B", pair_b()), ("C", pair_c())]:
    print(name, "psnr %.10f" % peak_signal_noise_ratio(a, b, data_range=1.0), "ssim %.10f" % ssim(a, b))
