#!/usr/bin/python3
"""The experiments of docs/methods/asvgf.md, as Markdown tables on stdout.

1. Lag after a light change: the built-in `lightswitch` scene (ceiling lamp off at frame 17 and
   on again at frame 33, 1-based; still camera, a ball and its shadow move), per method the
   frames after each change until the error (RMSE, linear HDR, against the reference) first
   falls within 10% of its steady value under the new lighting; 0 = the first frame after the
   change already is. Steady values: lamp off, the mean of frames 29-32 (the end of the dark
   period); lamp on, the mean of frames 13-16 (lit, before the first switch), because 16 frames
   after the second switch some methods are still converging.
2. SSIM / PSNR (tone-mapped, after the warm-up frames) per method on the built-in scenes: the
   A-SVGF and BMFR columns of the Higginson thesis's Table 3.1, in kind.
   Then the ghosting scene's RMSE and temporal error against the reference per method.
3. Reflected normals on and off (thesis Fig. 3.6) on the mirror scenes `ghosting` and `glossy`.
4. Time per a-trous level and per gradient pass at 1280x720 (`rtdenoise bench`).

Renders are small (the machine is shared): RTD_EXP_SIZE (160x90), RTD_EXP_FRAMES (24 for the
scene table; lightswitch always its 48), RTD_EXP_SPP (256, lightswitch's reference samples),
RTD_EXP_SCENE_SPP (128, the other scenes'), RTD_EXP_THREADS (1, for renders and denoising; the
benchmark uses all cores). References are cached (rtdenoise render's reference cache). Usage:
  scripts/asvgf-experiments.py [--rtdenoise build/release/apps/rtdenoise] [--work DIR] [--skip-bench]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

METHODS = ["accumulate", "svgf", "bmfr", "asvgf"]
SCENES = ["cornell", "pillars", "glossy", "dynamic", "lightswitch", "ghosting"]
LIGHT_CHANGES = [16, 32]  # 0-based frame indices of lightswitch's switches (off, on)


def run(cmd):
    print("+ " + " ".join(cmd), file=sys.stderr)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


THREADS = os.environ.get("RTD_EXP_THREADS", "1")


def render(exe, scene, out, size, frames, spp):
    if os.path.exists(os.path.join(out, "sequence.json")):
        return
    cmd = [exe, "render", "--scene", scene, "--output", out, "--size", size, "--reference-spp", str(spp),
           "--threads", THREADS]
    if frames:
        cmd += ["--frames", str(frames)]
    run(cmd)


def compare(exe, seq, out, methods, settings=()):
    """Runs `compare` once per work directory (delete its metrics.json to rerun)."""
    if os.path.exists(os.path.join(out, "metrics.json")):
        with open(os.path.join(out, "metrics.json")) as f:
            return {r["label"]: r for r in json.load(f)["runs"]}
    cmd = [exe, "compare", "--input", seq, "--reference", os.path.join(seq, "reference"), "--output", out,
           "--overwrite", "--methods", ",".join(methods), "--flip", "none", "--threads", THREADS]
    for s in settings:
        cmd += ["--set", s]
    run(cmd)
    with open(os.path.join(out, "metrics.json")) as f:
        return {r["label"]: r for r in json.load(f)["runs"]}


def denoise_eval(exe, seq, out, method, settings=()):
    cmd = [exe, "denoise", "--method", method, "--input", seq, "--output", out, "--overwrite", "--threads", THREADS]
    for s in settings:
        cmd += ["--set", s]
    run(cmd)
    metrics = out + ".json"
    run([exe, "eval", "--reference", os.path.join(seq, "reference"), "--result", out, "--flip", "none",
         "--json", metrics])
    with open(metrics) as f:
        return json.load(f)["streams"][0]


def recovery(errors, change, end, steady):
    """Frames after `change` until the error first falls within 10% of `steady`; None if it does
    not before `end`."""
    for k in range(change, end):
        if errors[k] <= 1.1 * steady:
            return k - change
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtdenoise", default="build/release/apps/rtdenoise")
    ap.add_argument("--work", default=os.path.join(tempfile.gettempdir(), "rtd-asvgf-experiments"))
    ap.add_argument("--skip-bench", action="store_true")
    ap.add_argument("--scenes", default=",".join(SCENES))
    a = ap.parse_args()
    exe = a.rtdenoise
    size = os.environ.get("RTD_EXP_SIZE", "160x90")
    frames = int(os.environ.get("RTD_EXP_FRAMES", "24"))
    spp = int(os.environ.get("RTD_EXP_SPP", "256"))
    scene_spp = int(os.environ.get("RTD_EXP_SCENE_SPP", "128"))
    os.makedirs(a.work, exist_ok=True)

    # 1. Lag after the light changes.
    seq = os.path.join(a.work, "lightswitch")
    render(exe, "lightswitch", seq, size, 0, spp)
    runs = compare(exe, seq, os.path.join(a.work, "lightswitch-compare"), METHODS)
    print(f"### Frames until the error after a light change is within 10% of its steady value\n")
    print(f"`lightswitch`, {size}, {spp}-spp references; RMSE (linear HDR); steady: lamp off = mean of "
          f"frames 29-32, lamp on = mean of frames 13-16; 0 = already in the first frame after the change; "
          f"'> n' = not within the n frames before the next change or the end.\n")
    print("| method | lamp off (frame 17) | lamp on (frame 33) | RMSE 1st frame after off / steady | RMSE 1st frame after on / steady |")
    print("|---|---|---|---|---|")
    off, on = LIGHT_CHANGES
    for m in METHODS:
        err = [f["rmse"] for f in runs[m]["frames"]]
        cells, ratios = [], []
        for change, end, steady in ((off, on, sum(err[on - 4:on]) / 4.0), (on, len(err), sum(err[off - 4:off]) / 4.0)):
            k = recovery(err, change, end, steady)
            cells.append(f"{k}" if k is not None else f"> {end - change - 1}")
            ratios.append(f"{err[change]:.3f} / {steady:.3f}")
        print(f"| {m} | {cells[0]} | {cells[1]} | {ratios[0]} | {ratios[1]} |")
    print()

    # 2. SSIM / PSNR per scene.
    scenes = a.scenes.split(",")
    table = {}
    for sc in scenes:
        seq = os.path.join(a.work, sc) if sc != "lightswitch" else os.path.join(a.work, "lightswitch")
        render(exe, sc, seq, size, frames if sc != "lightswitch" else 0, spp if sc == "lightswitch" else scene_spp)
        table[sc] = runs if sc == "lightswitch" else compare(exe, seq, os.path.join(a.work, sc + "-compare"), METHODS)
    for metric, label in (("ssim", "SSIM"), ("psnr", "PSNR [dB]")):
        print(f"### {label} per method and scene (tone-mapped, mean after the min(8, frames / 4) warm-up frames)\n")
        print(f"{size}, {frames} frames ({'lightswitch' in scenes and f'lightswitch 48 frames and {spp}-spp references, ' or ''}"
              f"{scene_spp}-spp references).\n")
        print("| method | " + " | ".join(scenes) + " |")
        print("|---|" + "---|" * len(scenes))
        for m in ["input"] + METHODS:
            print(f"| {m} | " + " | ".join(f"{table[sc][m]['steady'][metric]:.3f}" for sc in scenes) + " |")
        print()

    # 2b. Ghosting on the mirror floor (the thesis's demo, its Sec. 1.3.2).
    if "ghosting" in scenes:
        g = table["ghosting"]
        print("### Ghosting: the mirror floor under the rotating camera\n")
        print(f"`ghosting`, {size}, {frames} frames, {scene_spp}-spp references; means after the warm-up. "
              "RMSE in linear HDR; temporal error vs reference: mean |change of the result - change of the "
              "reference| between frames (docs/evaluation.md), where flicker, lag and ghosting show.\n")
        print("| method | RMSE | temporal error vs reference |")
        print("|---|---|---|")
        for m in ["input"] + METHODS:
            st = g[m]["steady"]
            print(f"| {m} | {st['rmse']:.4f} | {st['temporalErrorVsReference']:.4f} |")
        print()

    # 3. Reflected normals on the mirror scenes.
    print("### Reflected normals (thesis Fig. 3.6)\n")
    print("| scene | SSIM on | SSIM off | PSNR on | PSNR off |")
    print("|---|---|---|---|---|")
    for sc in [s for s in ("ghosting", "glossy") if s in scenes]:
        seq = os.path.join(a.work, sc)
        on = denoise_eval(exe, seq, os.path.join(a.work, sc + "-rn-on"), "asvgf")
        off = denoise_eval(exe, seq, os.path.join(a.work, sc + "-rn-off"), "asvgf", ["reflectedNormals=false"])
        print(f"| {sc} | {on['steady']['ssim']:.4f} | {off['steady']['ssim']:.4f} | "
              f"{on['steady']['psnr']:.2f} | {off['steady']['psnr']:.2f} |")
    print()

    # 4. Time per pass.
    if not a.skip_bench:
        out = os.path.join(a.work, "bench.json")
        run([exe, "bench", "--method", "asvgf", "--size", "1280x720", "--json", out])
        with open(out) as f:
            b = json.load(f)
        passes = b["passesMedianMs"]
        atrous = [v for k, v in passes.items() if k.startswith("atrous")]
        print("### Time per pass, 1280x720, CPU\n")
        print("| pass | ms |")
        print("|---|---|")
        for k, v in passes.items():
            print(f"| {k} | {v:.2f} |")
        if atrous:
            print(f"| a-trous level (mean of {len(atrous)}) | {sum(atrous) / len(atrous):.2f} |")
        print()


if __name__ == "__main__":
    main()
