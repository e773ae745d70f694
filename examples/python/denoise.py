"""The Python bindings in one program (docs/integration.md): the scene of examples/common/scene.h
(a textured wall scrolling right by one pixel per frame, 1-spp-like noise) denoised with numpy
arrays. Fails unless denoising removed most of the noise.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/denoise.py [method]
"""
import sys

import numpy as np

import rtdenoise

W, H, FRAMES = 64, 48, 8
y, x = np.mgrid[0:H, 0:W]


def scene(t):
    """Albedo, clean and noisy colour of frame t (H x W x 3 each)."""
    albedo = np.where(((x - t + 64) // 8 + y // 8) % 2 == 1, 0.8, 0.2)
    light = 1.0 + 0.5 * np.sin(0.1 * (x - t)) * np.cos(0.13 * y)
    h = (x.astype(np.uint32) * np.uint32(73856093)) ^ (y.astype(np.uint32) * np.uint32(19349663)) ^ np.uint32(t * 83492791)
    h = (h ^ (h >> np.uint32(13))) * np.uint32(1274126177)
    noise = -np.log((((h >> np.uint32(8)) & np.uint32(0xFFFFFF)).astype(np.float64) + 0.5) / 16777216.0)
    rgb = lambda v: np.repeat(v[..., None], 3, axis=2).astype(np.float32)
    return rgb(albedo), rgb(albedo * light), rgb(albedo * light * noise)


def main():
    method = sys.argv[1] if len(sys.argv) > 1 else "svgf"
    den = rtdenoise.Device("cpu").create_denoiser(method)
    normal = np.zeros((H, W, 3), np.float32)
    normal[..., 2] = 1.0                          # world space, facing the camera
    depth = np.full((H, W), 5.0, np.float32)       # linear view depth
    motion = np.zeros((H, W, 2), np.float32)
    motion[..., 0] = -1.0                         # pixel x was at x - 1 in the previous frame
    for t in range(FRAMES):
        albedo, clean, color = scene(t)
        out = den.denoise(color=color, albedo=albedo, normal=normal, depth=depth, motion=motion)  # den.reset() on a cut
    rmse_in = float(np.sqrt(np.mean((color - clean) ** 2)))
    rmse_out = float(np.sqrt(np.mean((out - clean) ** 2)))
    print(f"{den.method}, rtdenoise {rtdenoise.__version__}: RMSE of frame {FRAMES}: input {rmse_in:.4f}, output {rmse_out:.4f}")
    for name, ms in den.timings.items():
        print(f"  {name:<24} {ms:8.3f} ms")
    return 0 if rmse_out < 0.5 * rmse_in else 1


if __name__ == "__main__":
    sys.exit(main())
