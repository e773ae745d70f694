#!/usr/bin/env python3
"""The shared TAA pass's history filter and domain (issue 12): quality of every method that runs
TAA with taaHistoryFilter=bilinear, =catmullRom and with taa=false (--compare filter), or with
taaDomain=display, =linear and taa=false (--compare domain), taaOwnSurface=false, =true and
taa=false (--compare ownSurface), taaHistoryRejection off and on (--compare rejection), or both
(--compare combined), taaSubpixelAlpha 0, 1, 2 and 4 (--compare subpixel), or the defaults against
rtdenoise before issue 12 (--compare history), on the renderer's scenes and the committed Blender
fixtures with a reference; prints the Markdown tables of docs/methods/taa.md.

  scripts/taa-experiments.py [--build build/release] [--size 160x90] [--frames 16]
                             [--reference-spp 64] [--work /tmp/rtd-taa] [--scenes cornell,...]
                             [--compare filter|domain|ownSurface|rejection|combined]

Each scene is rendered once into WORK/<scene> (1 spp, --reference-spp references, kept for
re-runs), then one `rtdenoise compare` runs every configuration over it; the table holds the
means after compare's warm-up (frames 5-16 of 16; on the 8-frame Blender fixture frames 5-8):
PSNR and SSIM of ACES-tone-mapped sRGB, temporal = temporalErrorVsReference.
"""
import argparse
import json
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METHODS = ["svgf", "svgf:variant=dundr", "bmfr", "asvgf"]
# The configurations each table compares (--compare): the history filter, or the TAA's domain.
COMPARISONS = {
    "filter": [("bilinear", ":taaHistoryFilter=bilinear"), ("catmullRom", ":taaHistoryFilter=catmullRom"), ("no TAA", ":taa=false")],
    "domain": [("display", ":taaDomain=display"), ("linear", ":taaDomain=linear"), ("no TAA", ":taa=false")],
    "ownSurface": [("plain", ":taaOwnSurface=false"), ("own", ":taaOwnSurface=true"), ("no TAA", ":taa=false")],
    "rejection": [("off", ":taaHistoryRejection=false"), ("on", ":taaHistoryRejection=true")],
    # The two together against each alone and against no TAA (docs/methods/taa.md, "The defaults").
    "combined": [("neither", ":taaOwnSurface=false:taaHistoryRejection=false"), ("rejection", ":taaOwnSurface=false:taaHistoryRejection=true"),
                 ("ownSurface", ":taaOwnSurface=true:taaHistoryRejection=false"), ("both", ":taaOwnSurface=true:taaHistoryRejection=true"),
                 ("no TAA", ":taa=false")],
    # taaSubpixelAlpha: constant alpha against its rise with the history fetch's subpixel offset (docs/methods/taa.md).
    "subpixel": [("0", ":taaSubpixelAlpha=0"), ("1", ":taaSubpixelAlpha=1"), ("2", ":taaSubpixelAlpha=2"),
                 ("4", ":taaSubpixelAlpha=4")],
    # rtdenoise before issue 12 (linear domain, plain box, no rejection, bilinear history; with --before-build the
    # build of that time), the defaults of the morning of 2026-12-03 (bilinear history, rejection on; today's
    # taaSubpixelAlpha), the defaults (Catmull-Rom history, rejection off, taaSubpixelAlpha 2; BMFR 0), no TAA.
    "history": [("before issue 12", ":taaDomain=linear:taaOwnSurface=false:taaHistoryRejection=false:taaHistoryFilter=bilinear"),
                ("2026-12-03 morning", ":taaHistoryFilter=bilinear:taaHistoryRejection=true"), ("defaults", ""),
                ("no TAA", ":taa=false")],
}
SCENES = ["cornell", "pillars", "dynamic", "corridorglossy", "mirrorfloor", "glossyfloor"]


def run(cmd):
    print("+", " ".join(cmd), file=sys.stderr, flush=True)
    return subprocess.run(["nice", "-n", "10"] + cmd, check=True, text=True, stdout=subprocess.PIPE).stdout


def scene_arg(cli, name, work):
    if name != "glossyfloor":
        return name
    # mirrorfloor with a glossy floor (metallic, roughness 0.1), as scripts/reflections-experiments.py.
    scene = json.loads(run([cli, "render", "--print-scene", "mirrorfloor"]))
    scene["name"] = "glossyfloor"
    scene["materials"]["mirror"] = {"baseColor": [0.9, 0.9, 0.9], "metallic": 1, "roughness": 0.1}
    path = os.path.join(work, "glossyfloor.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def before_issue12(build, seq, methods, suffix, work, name):
    """The methods' defaults in the build before issue 12, under the names of the first column's runs. That build
    refuses buffers added since (e.g. indirectDiffuse): it reads a copy of the sequence whose sequence.json lists
    only the buffers it knows (the frames are links)."""
    old = os.path.join(build, "apps", "rtdenoise")
    native = os.path.exists(os.path.join(seq, "sequence.json"))  # else a Blender sequence: read as it is
    copy = os.path.join(work, "pre12-" + name) if native else seq
    desc = {}
    if native:
        os.makedirs(copy, exist_ok=True)
        with open(os.path.join(seq, "sequence.json")) as f:
            desc = json.load(f)
        for entry in os.listdir(seq):
            if entry != "sequence.json" and not os.path.lexists(os.path.join(copy, entry)):
                os.symlink(os.path.join(seq, entry), os.path.join(copy, entry))
    metrics = os.path.join(work, "metrics-pre12-" + name + ".json")
    while True:
        if native:
            with open(os.path.join(copy, "sequence.json"), "w") as f:
                json.dump(desc, f)
        cmd = [old, "compare", "-i", copy, "-r", os.path.join(seq, "reference"), "-o", os.path.join(work, "compare-pre12-" + name),
               "--overwrite", "--json", metrics] + [x for m in methods for x in ("-m", m)]
        p = subprocess.run(["nice", "-n", "10"] + cmd, text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        unknown = re.search(r'unknown buffer "(\w+)"', p.stderr)
        if unknown and unknown.group(1) in desc.get("buffers", []):
            desc["buffers"].remove(unknown.group(1))
            continue
        if p.returncode:
            raise SystemExit("the build before issue 12 failed on %s:\n%s" % (name, p.stderr))
        break
    with open(metrics) as f:
        d = json.load(f)
    return {r["config"] + suffix: r["steady"] for r in d["runs"] if r.get("method")}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--size", default="160x90")
    ap.add_argument("--frames", default="16")
    ap.add_argument("--reference-spp", default="64")
    ap.add_argument("--work", default="/tmp/rtd-taa")
    ap.add_argument("--scenes", default=",".join(SCENES + ["blender_glossy", "blender_lamp"]))
    ap.add_argument("--json", help="also write every run's steady-state means here")
    ap.add_argument("--before-build", help="with --compare history: the release build of rtdenoise before issue 12 (git "
                    "worktree add ../pre12 d80a5b6^; cmake --preset release; cmake --build build/release --target "
                    "rtdenoise_cli): its defaults give the first column instead of today's code with the old TAA settings")
    ap.add_argument("--compare", choices=sorted(COMPARISONS), default="filter",
                    help="filter: taaHistoryFilter bilinear / catmullRom / no TAA; domain: taaDomain display / linear / no TAA; "
                    "ownSurface: taaOwnSurface off / on / no TAA; rejection: taaHistoryRejection off / on; "
                    "combined: neither / rejection / ownSurface / both / no TAA; "
                    "subpixel: taaSubpixelAlpha 0 / 1 / 2 / 4; "
                    "history: before issue 12 / the defaults of 2026-12-03 morning / defaults / no TAA")
    a = ap.parse_args()
    TAA = COMPARISONS[a.compare]
    cli = os.path.join(a.build, "apps", "rtdenoise")
    os.makedirs(a.work, exist_ok=True)
    rows, everything = [], {}
    for name in a.scenes.split(","):
        # The Blender fixtures have no gradientSample buffer, which A-SVGF needs.
        methods = [m for m in METHODS if not (name.startswith("blender") and m == "asvgf")]
        configs = ["accumulate"] + [m + t for m in methods for _, t in TAA]
        if name.startswith("blender"):
            seq = os.path.join(ROOT, "tests", "fixtures", name)
        else:
            seq = os.path.join(a.work, name)
            if not os.path.exists(os.path.join(seq, "reference")):
                run([cli, "render", "--scene", scene_arg(cli, name, a.work), "--size", a.size, "--frames", a.frames,
                     "--reference-spp", a.reference_spp, "-o", seq, "--no-reference-cache"])
        out = os.path.join(a.work, "compare-" + name)
        metrics = os.path.join(a.work, "metrics-" + name + ".json")
        cmd = [cli, "compare", "-i", seq, "-r", os.path.join(seq, "reference"), "-o", out, "--overwrite", "--json", metrics]
        for c in configs:
            cmd += ["-m", c]
        run(cmd)
        with open(metrics) as f:
            d = json.load(f)
        res = {}
        for r in d["runs"]:
            if r.get("method"):
                res[r["config"]] = r["steady"]
        if a.before_build and a.compare == "history":
            res.update(before_issue12(a.before_build, seq, methods, TAA[0][1], a.work, name))
        everything[name] = res
        for m in ["accumulate"] + methods:
            label = m.replace("svgf:variant=dundr", "dundr")
            cells = []
            keys = [m] if m == "accumulate" else [m + t for _, t in TAA]
            for key in keys:
                s = next((v for k, v in res.items() if k == key or k.replace(":", "") == key.replace(":", "")), None)
                if s is None:  # compare names a run by what sets it apart: match on the settings
                    raise SystemExit("no run %s in %s (have %s)" % (key, metrics, list(res)))
                cells.append(s)
            def col(k, fmt):
                return " / ".join(fmt % c[k] for c in cells)
            rows.append("| %s | %s | %s | %s | %s |" % (name, label, col("psnr", "%.2f"), col("ssim", "%.4f"),
                                                        col("temporalErrorVsReference", "%.4f")))
    print("Columns: " + " / ".join(label for label, _ in TAA))
    print("| scene | method | PSNR [dB] | SSIM | temporal |")
    print("|---|---|---|---|---|")
    print("\n".join(rows))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(everything, f, indent=1)


if __name__ == "__main__":
    main()
