#!/usr/bin/python3
"""The experiments of docs/methods/asvgf.md, as Markdown tables on stdout.

1. Lag after a light change: the built-in `lightswitch` scene (ceiling lamp off at frame 17 and
   on again at frame 33, 1-based; still camera), per method the frames after each change until
   the error (RMSE, linear HDR, against the reference) is and stays within 10% of its steady
   value (the mean of the last 4 frames before the next change or the end).
2. SSIM / PSNR (tone-mapped, after the warm-up frames) per method on the built-in scenes: the
   A-SVGF and BMFR columns of the Higginson thesis's Table 3.1, in kind.
3. Reflected normals on and off (thesis Fig. 3.6) on the mirror scenes `ghosting` and `glossy`.
4. Time per a-trous level and per gradient pass at 1280x720 (`rtdenoise bench`).

Renders are small (the machine is shared): RTD_EXP_SIZE (160x90), RTD_EXP_FRAMES (32 for the
scene table; lightswitch always its 48), RTD_EXP_SPP (256, reference samples). References are
cached (rtdenoise render's reference cache). Usage:
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


def render(exe, scene, out, size, frames, spp):
    if os.path.exists(os.path.join(out, "sequence.json")):
        return
    cmd = [exe, "render", "--scene", scene, "--output", out, "--size", size, "--reference-spp", str(spp)]
    if frames:
        cmd += ["--frames", str(frames)]
    run(cmd)


def compare(exe, seq, out, methods, settings=()):
    cmd = [exe, "compare", "--input", seq, "--reference", os.path.join(seq, "reference"), "--output", out,
           "--methods", ",".join(methods), "--no-flip"]
    for s in settings:
        cmd += ["--set", s]
    run(cmd)
    with open(os.path.join(out, "metrics.json")) as f:
        return {r["label"]: r for r in json.load(f)["runs"]}


def denoise_eval(exe, seq, out, method, settings=()):
    cmd = [exe, "denoise", "--method", method, "--input", seq, "--output", out]
    for s in settings:
        cmd += ["--set", s]
    run(cmd)
    run([exe, "eval", "--reference", os.path.join(seq, "reference"), "--result", out, "--no-flip"])
    with open(os.path.join(out, "metrics.json")) as f:
        return json.load(f)


def recovery(errors, change, end):
    """Frames after `change` until errors stay within 10% of the steady value before `end`."""
    steady = sum(errors[end - 4:end]) / 4.0
    k = end
    while k > change and errors[k - 1] <= 1.1 * steady:
        k -= 1
    return k - change, steady


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtdenoise", default="build/release/apps/rtdenoise")
    ap.add_argument("--work", default=os.path.join(tempfile.gettempdir(), "rtd-asvgf-experiments"))
    ap.add_argument("--skip-bench", action="store_true")
    ap.add_argument("--scenes", default=",".join(SCENES))
    a = ap.parse_args()
    exe = a.rtdenoise
    size = os.environ.get("RTD_EXP_SIZE", "160x90")
    frames = int(os.environ.get("RTD_EXP_FRAMES", "32"))
    spp = int(os.environ.get("RTD_EXP_SPP", "256"))
    os.makedirs(a.work, exist_ok=True)

    # 1. Lag after the light changes.
    seq = os.path.join(a.work, "lightswitch")
    render(exe, "lightswitch", seq, size, 0, spp)
    runs = compare(exe, seq, os.path.join(a.work, "lightswitch-compare"), METHODS)
    print(f"### Frames until the error after a light change is within 10% of its steady value\n")
    print(f"`lightswitch`, {size}, {spp}-spp references; RMSE (linear HDR); steady = mean of the last "
          f"4 frames before the next change.\n")
    print("| method | lamp off (frame 17) | lamp on (frame 33) | RMSE 1st frame after off / steady | RMSE 1st frame after on / steady |")
    print("|---|---|---|---|---|")
    ends = LIGHT_CHANGES[1:] + [None]
    for m in METHODS:
        err = [f["rmse"] for f in runs[m]["frames"]]
        cells, ratios = [], []
        for change, end in zip(LIGHT_CHANGES, ends):
            k, steady = recovery(err, change, end or len(err))
            cells.append(f"{k}")
            ratios.append(f"{err[change]:.3f} / {steady:.3f}")
        print(f"| {m} | {cells[0]} | {cells[1]} | {ratios[0]} | {ratios[1]} |")
    print()

    # 2. SSIM / PSNR per scene.
    scenes = a.scenes.split(",")
    table = {}
    for sc in scenes:
        seq = os.path.join(a.work, sc) if sc != "lightswitch" else os.path.join(a.work, "lightswitch")
        render(exe, sc, seq, size, frames if sc != "lightswitch" else 0, spp)
        table[sc] = compare(exe, seq, os.path.join(a.work, sc + "-compare"), METHODS)
    for metric, label in (("ssim", "SSIM"), ("psnr", "PSNR [dB]")):
        print(f"### {label} per method and scene (tone-mapped, mean after the 8 warm-up frames)\n")
        print(f"{size}, {frames} frames ({'lightswitch' in scenes and 'lightswitch 48, ' or ''}"
              f"{spp}-spp references).\n")
        print("| method | " + " | ".join(scenes) + " |")
        print("|---|" + "---|" * len(scenes))
        for m in ["input"] + METHODS:
            print(f"| {m} | " + " | ".join(f"{table[sc][m]['steady'][metric]:.3f}" for sc in scenes) + " |")
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
