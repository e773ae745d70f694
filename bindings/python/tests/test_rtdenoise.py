"""Tests of the Python bindings (run by ctest with Debian's /usr/bin/python3 and the build tree's
package on PYTHONPATH). Expected values are worked out here from the definitions (accumulation
weights, PSNR of a known error), not taken from the code under test."""
import math
import re

import numpy as np
import pytest

import rtdenoise

H, W = 12, 20


def frame(seed, h=H, w=W):
    """A frame of noisy colour on constant guides (albedo 0.5, normal +z, depth 2, zero motion)."""
    rng = np.random.default_rng(seed)
    c = rng.uniform(0.1, 1.0, (h, w, 3)).astype(np.float32)
    a = np.full((h, w, 3), 0.5, np.float32)
    n = np.zeros((h, w, 3), np.float32)
    n[..., 2] = 1
    z = np.full((h, w), 2.0, np.float32)
    m = np.zeros((h, w, 2), np.float32)
    return dict(color=c, albedo=a, normal=n, depth=z, motion=m)


def test_smallest_use_denoises_an_array():
    f0, f1 = frame(0), frame(1)
    den = rtdenoise.Device("cpu").create_denoiser("accumulate")
    out = den.denoise(color=f0["color"], albedo=f0["albedo"], normal=f0["normal"], depth=f0["depth"], motion=f0["motion"])
    assert out.shape == (H, W, 3) and out.dtype == np.float32
    # The first frame has no history: the output is the input.
    np.testing.assert_allclose(out, f0["color"], rtol=1e-6)
    # The second, with zero motion and matching guides, is the mean of both (w = max(1/2, alpha)).
    out = den.denoise(**f1)
    np.testing.assert_allclose(out, 0.5 * (f0["color"] + f1["color"]), rtol=1e-5)


def test_version_devices_and_methods():
    assert re.fullmatch(r"\d+\.\d+\.\d+", rtdenoise.__version__)
    assert tuple(int(x) for x in rtdenoise.__version__.split(".")) == rtdenoise.version_info
    devices = rtdenoise.list_devices()
    assert devices[0]["backend"] == "cpu"
    methods = {m["name"]: m for m in rtdenoise.list_methods()}
    assert {"accumulate", "svgf", "bmfr"} <= set(methods)
    alpha = [s for s in methods["accumulate"]["settings"] if s["name"] == "alpha"][0]
    assert alpha["type"] == "float" and alpha["value"] == pytest.approx(0.2)
    assert rtdenoise.buffer_names()[:6] == ["color", "albedo", "normal", "depth", "position", "motion"]
    assert rtdenoise.buffer_channels("motion") == 2


def test_settings_round_trip():
    den = rtdenoise.Device("cpu").create_denoiser("svgf", atrousIterations=3, sigmaLuminance=2.5)
    assert den.method == "svgf" and den.backend == "cpu"
    assert den.required_buffers == ["color", "normal", "depth"]
    assert den.get("atrousIterations") == 3
    assert den.get("sigmaLuminance") == pytest.approx(2.5)
    den.set("sigmaLuminance", 6.0)
    den.set("atrousIterations", 4)
    s = den.settings
    assert s["sigmaLuminance"] == pytest.approx(6.0) and s["atrousIterations"] == 4
    # bools and enums by their Python values
    acc = rtdenoise.Device().create_denoiser("accumulate")
    acc.set("demodulate", False)
    assert acc.get("demodulate") is False
    info = {i["name"]: i for i in den.settings_info()}
    assert info["sigmaLuminance"]["type"] == "float" and info["sigmaLuminance"]["doc"]


def test_bad_setting_raises_with_the_library_message():
    den = rtdenoise.Device().create_denoiser("accumulate")
    with pytest.raises(rtdenoise.Error, match="has no setting 'alpah'"):
        den.set("alpah", 0.1)
    with pytest.raises(rtdenoise.Error, match=r"alpha.*outside \[0\.001, 1\]"):
        den.set("alpha", 7)
    with pytest.raises(ValueError):  # rtdenoise.Error is a ValueError
        den.set("demodulate", "maybe")
    assert den.get("alpha") == pytest.approx(0.2)  # nothing changed
    with pytest.raises(rtdenoise.Error, match="unknown method 'nope'"):
        rtdenoise.Device().create_denoiser("nope")
    with pytest.raises(rtdenoise.Error):
        rtdenoise.Device().create_denoiser("svgf", noSuchSetting=1)
    with pytest.raises(ValueError, match="backend"):
        rtdenoise.Device("gpu")


def test_wrong_shape_raises_before_anything_runs():
    """A bad call changes nothing: the next frame is what a twin that never saw it makes."""
    dev = rtdenoise.Device()
    den, twin = dev.create_denoiser("svgf"), dev.create_denoiser("svgf")
    f0, f1 = frame(0), frame(1)
    den.denoise(**f0)
    twin.denoise(**f0)
    timings = den.timings
    bad = [
        dict(f1, normal=f1["normal"][..., :2]),            # 2 channels for a 3-channel buffer
        dict(f1, depth=f1["depth"][:-1]),                  # a row short
        dict(f1, motion=f1["motion"].reshape(-1)),         # one dimension
        dict(f1, color=np.zeros((H, W, 5), np.float32)),   # 5 channels
        {k: v for k, v in f1.items() if k != "depth"},     # svgf needs depth
    ]
    for b in bad:
        with pytest.raises(ValueError):
            den.denoise(**b)
    with pytest.raises(ValueError, match="output"):
        den.denoise(**f1, output=np.zeros((H, W, 2), np.float32))
    with pytest.raises(TypeError, match="unknown argument 'colour'"):
        den.denoise(colour=f1["color"])
    assert den.timings == timings  # no frame ran
    np.testing.assert_array_equal(den.denoise(**f1), twin.denoise(**f1))


def test_arrays_are_read_and_written_in_place():
    f = frame(3)
    den_a, den_b = rtdenoise.Device().create_denoiser("svgf"), rtdenoise.Device().create_denoiser("svgf")
    # RGBA storage read through a strided RGB slice; a float64 copy is converted.
    rgba = np.concatenate([f["color"], np.ones((H, W, 1), np.float32)], axis=2)
    out = np.zeros((H, W, 4), np.float32)
    returned = den_a.denoise(**dict(f, color=rgba[..., :3]), output=out)
    assert returned is out and np.all(out[..., 3] == 1)
    expected = den_b.denoise(**dict(f, color=f["color"].astype(np.float64)))
    np.testing.assert_array_equal(out[..., :3], expected)


def test_half_arrays():
    f = frame(4)
    halves = {k: v.astype(np.float16) for k, v in f.items()}
    floats = {k: v.astype(np.float32) for k, v in halves.items()}  # the same values
    den_h, den_f = rtdenoise.Device().create_denoiser("svgf"), rtdenoise.Device().create_denoiser("svgf")
    out_h = den_h.denoise(**halves, output=np.zeros((H, W, 4), np.float16))
    out_f = den_f.denoise(**floats)
    np.testing.assert_array_equal(out_h[..., :3], out_f.astype(np.float16))


def test_timings_and_stats():
    den = rtdenoise.Device().create_denoiser("svgf")
    f = frame(5)
    f["color"][0, 0, 0] = np.nan
    den.denoise(**f)
    t = den.timings
    assert list(t)[0] == "import" and list(t)[-1].endswith("export")  # "taa+export" where TAA writes the output
    assert all(v >= 0 for v in t.values())
    s = den.stats
    assert s["sanitized_values"] == 1 and s["pixels"] == H * W and s["total_ms"] > 0
    assert s["notes"] == []


def test_stats_report_the_memory_held():
    # Colour, albedo, normal, depth and motion: 12 float channels per frame kept, and after the
    # second frame the previous frame's too.
    den = rtdenoise.Device().create_denoiser("svgf")
    den.denoise(**frame(0))
    den.denoise(**frame(1))
    m = den.stats["memory"]
    assert m["frames"] == 2 * 12 * H * W * 4
    assert m["planes"] > 0 and set(m) == {"frames", "planes"}


def test_reset_starts_the_stream_anew():
    den, fresh = rtdenoise.Device().create_denoiser("svgf"), rtdenoise.Device().create_denoiser("svgf")
    for i in range(3):
        den.denoise(**frame(i))
    den.reset()
    np.testing.assert_array_equal(den.denoise(**frame(9)), fresh.denoise(**frame(9)))


def test_conventions_motion_in_uv():
    """Motion given in UV (with the convention) denoises like the same motion in pixels."""
    frames = [frame(i) for i in range(3)]
    for f in frames:
        f["motion"][..., 0] = -1.0  # content moves one pixel right per frame
    den_px, den_uv = rtdenoise.Device().create_denoiser("svgf"), rtdenoise.Device().create_denoiser("svgf")
    for f in frames:
        a = den_px.denoise(**f)
        uv = f["motion"] / np.array([W, H], np.float32)
        b = den_uv.denoise(**dict(f, motion=uv), conventions={"motionUnits": "uv"})
        np.testing.assert_allclose(b, a, rtol=1e-5, atol=1e-6)
    with pytest.raises(rtdenoise.Error, match="no field 'motionUnit'"):
        den_uv.denoise(**frames[0], conventions={"motionUnit": "uv"})
    names = [c["name"] for c in rtdenoise.convention_settings()]
    assert "normalSpace" in names and "depth" in names


def test_sequence_round_trip(tmp_path):
    projection = np.array([[1.5, 0, 0, 0], [0, 2, 0, 0], [0, 0, -1.01, -0.2], [0, 0, -1, 0]])
    cam = rtdenoise.Camera(world_to_camera=np.eye(4), projection=projection)
    writer = rtdenoise.SequenceWriter(tmp_path / "seq")
    written = []
    for i in range(3):
        f = frame(i)
        fr = rtdenoise.Frame(number=i + 1, camera=cam, **f)
        writer.write(fr)
        written.append(f)
    writer.finish()
    reader = rtdenoise.SequenceReader(tmp_path / "seq")
    assert reader.kind == "native" and len(reader) == 3 and (reader.height, reader.width) == (H, W)
    assert set(reader.buffers) == {"color", "albedo", "normal", "depth", "motion"}
    den = rtdenoise.Device().create_denoiser("svgf")
    for i in range(3):
        fr = reader[i]
        assert fr.number == i + 1 and "color" in fr and "position" not in fr
        for name, array in written[i].items():
            np.testing.assert_array_equal(fr[name], array)
        np.testing.assert_allclose(fr.camera.projection, cam.projection)
        assert fr.camera.valid
        out = den.denoise(**fr.buffers, camera=fr.camera)
        assert out.shape == (H, W, 3)
    with pytest.raises(IndexError):
        reader.read(3)
    with pytest.raises(KeyError):
        reader[0]["position"]
    with pytest.raises(rtdenoise.Error):
        rtdenoise.SequenceReader(tmp_path / "missing")


def test_exr_round_trip(tmp_path):
    rgb = np.random.default_rng(1).uniform(0, 4, (H, W, 3)).astype(np.float32)
    rtdenoise.write_exr(tmp_path / "a.exr", rgb)
    np.testing.assert_array_equal(rtdenoise.read_exr(tmp_path / "a.exr"), rgb)


def test_eval_metrics_on_arrays():
    ref = np.zeros((16, 16, 3), np.float32)
    test = np.full((16, 16, 3), 0.1, np.float32)
    # MSE 0.01 against peak 1: 10 log10(1 / 0.01) = 20 dB.
    assert rtdenoise.eval.psnr(test, ref) == pytest.approx(20.0, abs=1e-4)
    assert math.isinf(rtdenoise.eval.psnr(ref, ref))
    assert rtdenoise.eval.rmse(test, ref) == pytest.approx(0.1, rel=1e-6)
    assert rtdenoise.eval.mse(test, ref) == pytest.approx(0.01, rel=1e-5)
    # relMSE: (0.1 - 0)^2 / (0^2 + 0.01) = 1
    assert rtdenoise.eval.rel_mse(test, ref) == pytest.approx(1.0, rel=1e-5)
    img = np.random.default_rng(2).uniform(0, 1, (24, 24, 3)).astype(np.float32)
    assert rtdenoise.eval.ssim(img, img) == pytest.approx(1.0)
    assert rtdenoise.eval.flip(img, img) == pytest.approx(0.0)
    mean, emap = rtdenoise.eval.flip(img, 1 - img, error_map=True)
    assert mean > 0 and emap.shape == (24, 24)
    ldr = rtdenoise.eval.tone_map(img * 4, op="clamp")
    np.testing.assert_array_equal(ldr.shape, img.shape)
    assert ldr.min() >= 0 and ldr.max() <= 1
    with pytest.raises(rtdenoise.Error):
        rtdenoise.eval.tone_map(img, op="filmic-ish")
    with pytest.raises(ValueError, match="3 channels"):
        rtdenoise.eval.psnr(img[..., :2], img[..., :2])
