#!/usr/bin/env python3
"""Gersthofer's evaluation (thesis Sec. 5, Tables 5.1-5.4) with rtdenoise's own scenes, written
as Markdown tables into docs/methods/stereo.md between the "experiments" markers.

  python3 scripts/stereo-experiments.py [--bin build/release/apps/rtdenoise] [--work DIR]
                                        [--size 96x54] [--frames 12] [--reference-spp 256]
                                        [--bench-size 1440x1600] [--only 5.1,5.2,5.3]

Table 5.1: every built-in scene rendered in stereo, denoised with the gersthofer variant (and,
for comparison, with eyeReprojection=false), each eye against the renderer's reference of the
same frames (`render --reference-spp`); MSE and SSIM averaged over the frames after the
warm-up. Table 5.2: the cornell scene traced at coverage c = 0.5, 0.25, 0.125 (the renderer's
blue-noise masks, `--sample-fraction`), denoised, against the fully traced denoised result.
Tables 5.3 and 5.4: `rtdenoise bench --stereo` at 1440x1600 per eye: per-pass CPU time of both
eyes and the memory the denoiser reports. Only the standard library; the CLI does the work.
References are cached by the renderer (its reference cache), so a second run is quick.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "methods" / "stereo.md"
SCENES = ["cornell", "glossy", "pillars", "dynamic"]


def run(args: list[str]) -> str:
    print("+", " ".join(args), file=sys.stderr, flush=True)
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(args)}\n{r.stdout}\n{r.stderr}")
    return r.stdout


def metrics(path: Path) -> dict:
    """Mean over the frames after the warm-up: MSE on linear HDR (RMSE^2), MSE on the
    tone-mapped sRGB image (10^(-PSNR/10)) and SSIM."""
    frames = [f for f in json.loads(path.read_text())["streams"][0]["frames"] if not f["warmup"]]
    n = len(frames)
    return {
        "frames": n,
        "mseHdr": sum(f["rmse"] ** 2 for f in frames) / n,
        "mseLdr": sum(10 ** (-f["psnr"] / 10) if f["psnr"] not in (None, "inf") else 0.0 for f in frames) / n,
        "ssim": sum(f["ssim"] for f in frames) / n,
    }


def evaluate(bin_: str, reference: Path, result: Path, warmup: int) -> dict:
    out = result / "metrics.json"
    run([bin_, "eval", "--reference", str(reference), "--result", str(result), "--warmup", str(warmup), "--no-flip",
         "--json", str(out)])
    return metrics(out)


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def table_5_1(a, work: Path) -> str:
    rows = []
    for scene in SCENES:
        d = work / f"t51_{scene}"
        run([a.bin, "render", "--scene", scene, "--stereo", "--frames", str(a.frames), "--size", a.size,
             "--reference-spp", str(a.reference_spp), "--output", str(d / "D")])
        results = {}
        for label, extra in (("shared", []), ("apart", ["--set", "eyeReprojection=false"])):
            o = d / f"O_{label}"
            run([a.bin, "denoise", "--method", "svgf", "--set", "variant=gersthofer", *extra, "--input", str(d / "D"),
                 "--output", str(o)])
            for eye in ("left", "right"):
                results[(label, eye)] = evaluate(a.bin, d / "D" / eye / "reference", o / eye, a.warmup)
        # The noisy 1-spp input, for scale.
        noisy = {eye: evaluate(a.bin, d / "D" / eye / "reference", d / "D" / eye, a.warmup) for eye in ("left", "right")}
        for eye in ("left", "right"):
            s, p, n = results[("shared", eye)], results[("apart", eye)], noisy[eye]
            rows.append(f"| {scene} | {eye} | {s['mseLdr']:.5f} | {s['ssim']:.4f} | {s['mseHdr']:.5f} | "
                        f"{p['mseLdr']:.5f} | {p['ssim']:.4f} | {n['mseLdr']:.4f} | {n['ssim']:.4f} |")
    w, h = a.size.split("x")
    return "\n".join([
        f"**Table 5.1** (thesis: RedRoom MSE 0.0428 / SSIM 0.6258 ... Sponza 0.0017 / 0.9441 at 1440x1600 against "
        f"1024 spp). Here: {w}x{h} per eye, {a.frames} frames (the first {a.warmup} are warm-up and left out), "
        f"reference {a.reference_spp} spp per frame (1024 spp is too slow on this shared 2-core machine), 1-spp input; "
        "MSE and SSIM on the ACES-tone-mapped sRGB image (`rtdenoise eval`), MSE HDR on linear radiance. "
        "'shared' is the gersthofer variant, 'apart' the same with eyeReprojection=false.",
        "",
        "| scene | eye | MSE | SSIM | MSE HDR | MSE apart | SSIM apart | MSE input | SSIM input |",
        "|---|---|---|---|---|---|---|---|---|",
        *rows,
    ])


def table_5_2(a, work: Path) -> str:
    d = work / "t52"
    frames = max(a.frames, 16)  # every pixel traced twice at c = 1/8
    outs = {}
    for c in (1.0, 0.5, 0.25, 0.125):
        tag = f"c{c:g}"
        run([a.bin, "render", "--scene", "cornell", "--stereo", "--frames", str(frames), "--size", a.size,
             "--sample-fraction", f"{c:g}", "--no-reference-cache", "--output", str(d / f"D_{tag}")])
        outs[c] = d / f"O_{tag}"
        run([a.bin, "denoise", "--method", "svgf", "--set", "variant=gersthofer", "--input", str(d / f"D_{tag}"),
             "--output", str(outs[c])])
    rows = []
    for c in (0.5, 0.25, 0.125):
        m = {eye: evaluate(a.bin, outs[1.0] / eye, outs[c] / eye, a.warmup) for eye in ("left", "right")}
        rows.append(f"| {c:g} | {m['left']['mseLdr']:.2e} | {m['left']['ssim']:.4f} | {m['right']['mseLdr']:.2e} | "
                    f"{m['right']['ssim']:.4f} |")
    w, h = a.size.split("x")
    return "\n".join([
        f"**Table 5.2** (thesis, RedRoom: c = 0.5 MSE 2.2e-5 / SSIM 0.9978, 0.25 5.6e-5 / 0.9956, 0.125 1.4e-4 / "
        f"0.9905). Here: cornell (slow camera pan), {w}x{h} per eye, {frames} frames (the first {a.warmup} left "
        "out), masked at coverage c against the fully traced sequence, both denoised with the gersthofer variant "
        "(MSE and SSIM on the tone-mapped image). Different coverages trace different random numbers, so part of "
        "the difference is noise the fully traced result also has.",
        "",
        "| coverage c | MSE left | SSIM left | MSE right | SSIM right |",
        "|---|---|---|---|---|",
        *rows,
    ])


def tables_5_3_5_4(a, work: Path) -> str:
    out = work / "t53.json"
    run([a.bin, "bench", "--method", "svgf", "--stereo", "--size", a.bench_size, "--set", "variant=gersthofer",
         "--frames", str(a.bench_frames), "--warmup", "2", "--json", str(out)])
    b = json.loads(out.read_text())
    passes = b["passesMedianMs"]
    order = ["import", "reproject", "features", "demodulate", "accumulate", "median", "eyeReprojection", "composite",
             "variance", "atrous1", "atrous2", "atrous3", "atrous4", "atrous5", "remodulate", "postprocess", "export"]
    rows = [f"| {name} | {passes[name]:.1f} |" for name in order if name in passes]
    rows += [f"| {name} | {v:.1f} |" for name, v in passes.items() if name not in order]
    atrous = sum(v for k, v in passes.items() if k.startswith("atrous"))
    mem = b.get("memoryBytes", {})
    mib = {k: v / 2 ** 20 for k, v in mem.items()}
    w, h = (int(v) for v in a.bench_size.split("x"))
    per = lambda k: mem.get(k, 0) / (2 * w * h)  # bytes per pixel per eye
    return "\n".join([
        f"**Table 5.3** (thesis, RTX 2070 Super, both eyes at 1440x1600: filter passes about 14 ms, spatial filter "
        f"about 10 ms, eye reprojection about 1 ms). Here: `rtdenoise bench --stereo --size {a.bench_size} "
        f"--set variant=gersthofer`, CPU ({cpu_model()}, {os.cpu_count()} cores, shared with other work: "
        f"noisy, medians of {b['frames']} frames), both eyes per pass (the passes sum the two eyes' times; "
        "eyeReprojection is both directions). The synthetic scene has one camera, so the right eye sees the left "
        "eye's view with other noise and every pixel reprojects (the exchange's most work). Vulkan on a GPU was not "
        "available this session (the Vulkan pipeline is tested on lavapipe only).",
        "",
        "| pass (both eyes) | ms |",
        "|---|---|",
        *rows,
        f"| **a-trous, 5 levels** | **{atrous:.1f}** |",
        f"| **total** | **{b['totalMedianMs']:.1f}** |",
        "",
        f"**Table 5.4** (thesis, both eyes at 1440x1600: G-buffer 246.09 MiB, history 36.47, masks 7.18, "
        f"intermediate 281.25, total 570.99 MiB). Here, as the library reports it (`FrameStats::memory`), both eyes:",
        "",
        "| category | MiB | bytes per pixel per eye |",
        "|---|---|---|",
        *[f"| {k} | {mib[k]:.2f} | {per(k):.1f} |" for k in ("frames", "history", "intermediate") if k in mib],
        f"| **total** | **{sum(mib.values()):.2f}** | **{sum(mem.values()) / (2 * w * h):.1f}** |",
        "",
        "'frames' are the imported inputs of the current and the previous frame (every buffer the pipeline reads, "
        "32-bit floats: the counterpart of the thesis's G-buffer, which packs 56 bytes per pixel at reduced "
        "precision); 'history' the composite and indirect-diffuse accumulators (colour, moments, length; double "
        "buffered) and the indirect ray length; the masks are the renderer's, not the denoiser's.",
    ])


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--bin", default=str(ROOT / "build" / "release" / "apps" / "rtdenoise"))
    p.add_argument("--work", default="/tmp/rtd-stereo-experiments")
    p.add_argument("--size", default="96x54")
    p.add_argument("--frames", type=int, default=12)
    p.add_argument("--warmup", type=int, default=4)
    p.add_argument("--reference-spp", type=int, default=256)
    p.add_argument("--bench-size", default="1440x1600")
    p.add_argument("--bench-frames", type=int, default=5)
    p.add_argument("--only", default="5.1,5.2,5.3", help="tables to make (5.3 includes 5.4)")
    a = p.parse_args()
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    want = set(a.only.split(","))
    makers = {"5.1": table_5_1, "5.2": table_5_2, "5.3": tables_5_3_5_4}
    text = DOC.read_text()
    if "## Experiments" not in text:
        text = text.rstrip() + "\n\n## Experiments\n\n(Made by `scripts/stereo-experiments.py`; each table between its markers.)\n"
    for key, make in makers.items():
        if key not in want:
            continue
        begin, end = f"<!-- table {key}: begin -->", f"<!-- table {key}: end -->"
        block = begin + "\n\n" + make(a, work) + "\n\n" + end
        if begin in text:
            text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda m: block, text, flags=re.S)
        else:
            text = text.rstrip() + "\n\n" + block + "\n"
        DOC.write_text(text)  # after each table: a later failure keeps the earlier ones
    print(f"wrote the tables into {DOC}")


if __name__ == "__main__":
    main()
