#!/usr/bin/env python3
"""Voorhuis 2018's experiments on the renderer's scenes; writes the tables of
docs/methods/reflections.md (between the 'experiments' markers).

  Fig. 8       quality: Base / NoSpecReproj / Ours, moving camera, RMSE and SSIM (whole, reflective)
  Fig. 9       stability: the same on 60 still frames, temporal error
  Figs. 12-13  reflection MVs vs the 200x200 brute force, LDSP scaling on / off
  Fig. 11      supersampling: 1 spp + TAA, 1 spp, 4 spp with guide rays
  Figs. 14-15  cost over Base at 1280x720 per pass (rtdenoise bench --input), guide-ray cost per spp

Usage: scripts/reflections-experiments.py [--build build/release] [--size 160x90] [--only quality,...]
Needs a release build (rtdenoise, rtd_reflections_experiment, rtd_bench). Runs niced; about
15 minutes on 2 shared cores (references are cached in the renderer's reference cache).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "methods", "reflections.md")
BEGIN, END = "<!-- experiments:begin -->", "<!-- experiments:end -->"


def run(cmd, **kw):
    print("+", " ".join(cmd), file=sys.stderr, flush=True)
    return subprocess.run(["nice", "-n", "10"] + cmd, check=True, text=True, stdout=subprocess.PIPE, **kw).stdout


def lines_json(text):
    return [json.loads(l) for l in text.splitlines() if l.startswith("{")]


def glossy_floor(cli, tmp):
    """mirrorfloor with a glossy floor (metallic, roughness 0.1): SPONZAGLOSSYFLOOR in kind."""
    scene = json.loads(run([cli, "render", "--print-scene", "mirrorfloor"]))
    scene["name"] = "glossyfloor"
    scene["materials"]["mirror"] = {"baseColor": [0.9, 0.9, 0.9], "metallic": 1, "roughness": 0.1}
    path = os.path.join(tmp, "glossyfloor.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def write_section(key, text):
    """Replaces (or appends) the block of section `key` between the experiments markers."""
    doc = open(DOC).read()
    if BEGIN not in doc or END not in doc:
        sys.exit("%s has no %s ... %s markers" % (DOC, BEGIN, END))
    head, rest = doc.split(BEGIN, 1)
    body, tail = rest.split(END, 1)
    b, e = "<!-- %s -->" % key, "<!-- /%s -->" % key
    block = "%s\n%s\n%s" % (b, text, e)
    if b in body:
        pre, post = body.split(b, 1)
        body = pre + block + post.split(e, 1)[1]
    else:
        body = body.rstrip("\n") + "\n\n" + block + "\n\n"
    with open(DOC, "w") as f:
        f.write(head + BEGIN + body + END + tail)
    print("wrote", key, "into", DOC, file=sys.stderr)


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--size", default="160x90")
    ap.add_argument("--only", default="quality,ablation,stability,motion,supersampling,cost",
                    help="comma-separated sections to run (each rewrites its own table)")
    ap.add_argument("--motion-frames", default="24", help="frames of the corridor flythroughs for Figs. 12-13")
    ap.add_argument("--quality-size", default="320x180",
                    help="Fig. 8 once more at this size (empty: not): the corridor's orb is 12 px across at 160x90")
    a = ap.parse_args()
    cli = os.path.join(a.build, "apps", "rtdenoise")
    exp = os.path.join(a.build, "bench", "rtd_reflections_experiment")
    bench = os.path.join(a.build, "bench", "rtd_bench")
    w, h = a.size.split("x")
    size = ["--width", w, "--height", h]
    only = set(a.only.split(","))
    lscpu = subprocess.run(["lscpu"], text=True, stdout=subprocess.PIPE).stdout
    model = re.search(r"Model name:\s*(.*)", lscpu)
    machine = "%s (%d cores)" % (model.group(1).strip() if model else "unknown CPU", os.cpu_count() or 0)
    if only == set(ap.get_default("only").split(",")):  # a partial run leaves the other sections' machine line
        write_section("machine", "Measured by `scripts/reflections-experiments.py` on %s, shared with other "
                      "jobs: timings are noisy." % machine)

    class Sections(list):
        def append(self, key_text):
            write_section(*key_text)

    sections = Sections()
    with tempfile.TemporaryDirectory(prefix="rtd-reflections-") as tmp:
        scenes = [("mirrorfloor", "mirrorfloor"), ("glossyfloor", glossy_floor(cli, tmp)),
                  ("corridorglossy", "corridorglossy")]

        # Fig. 8: quality on a moving camera.
        def scores(experiment, which, size=size):
            """Fig. 8's rows (RMSE, SSIM, whole and reflective) of `experiment` on the scenes `which`."""
            rows = []
            for label, scene in which:
                for r in lines_json(run([exp, "--experiment", experiment, "--scene", scene, "--frames", "24",
                                         "--eval-frames", "4", "--reference-spp", "256"] + size)):
                    rows.append([label, r["config"], "%.4f" % r["rmse"], "%.4f" % r["ssim"],
                                 "%.4f" % r["rmseReflective"], "%.4f" % r["ssimReflective"]])
            return rows

        # Fig. 8 adds the corridor past a mirror orb (the glossy one's twin): a curved mirror.
        quality_scenes = scenes + [("corridor", "corridor")]
        rows = scores("quality", quality_scenes if "quality" in only else [])
        if rows: sections.append(("fig8", "**Fig. 8 (quality, moving camera)**: %s, frames 0-23 of each scene's path, scored on the "
                        "last 4 against 256-spp references; RMSE of tone-mapped (ACES) images, SSIM of tone-mapped "
                        "sRGB; *reflective* = pixels of primary roughness < 0.4.\n\n" % a.size +
                        table(["scene", "config", "RMSE", "SSIM", "RMSE refl.", "SSIM refl."], rows)))

        # Fig. 8 at a second size: on the small scenes a reflective region of a hundred pixels and four frames decide.
        if "quality" in only and a.quality_size:
            w2, h2 = a.quality_size.split("x")
            rows = scores("quality", quality_scenes, ["--width", w2, "--height", h2])
            sections.append(("fig8-large", "**Fig. 8 at %s** (otherwise as above): the corridor's orb 24 px across instead "
                             "of 12, four times the reflective pixels per frame.\n\n" % a.quality_size +
                             table(["scene", "config", "RMSE", "SSIM", "RMSE refl.", "SSIM refl."], rows)))

        # Ablation: Fig. 8's scores with one part of Ours off at a time, on the glossy scenes.
        rows = scores("ablation", [s for s in scenes if s[0] != "mirrorfloor"] if "ablation" in only else [])
        if rows: sections.append(("ablation", "**Ablation (Fig. 8's setting)**: %s, the glossy scenes, Ours with one "
                        "part switched off at a time (`--set` after `variant=voorhuis`), and Base and NoSpecReproj "
                        "with and without TAA.\n\n" % a.size +
                        table(["scene", "config", "RMSE", "SSIM", "RMSE refl.", "SSIM refl."], rows)))

        # Fig. 9: temporal error on 60 still frames.
        rows = []
        for label, scene in (quality_scenes if "stability" in only else []):
            res = {r["config"]: r for r in lines_json(run([exp, "--experiment", "stability", "--scene", scene,
                                                            "--frames", "60", "--still-frame", "20"] + size))}
            ours = res["Ours"]["temporalErrorReflective"]
            for cfg, r in res.items():
                rows.append([label, cfg, "%.5f" % r["temporalError"], "%.5f" % r["temporalErrorReflective"],
                             "%.2f" % (r["temporalErrorReflective"] / ours)])
        if rows: sections.append(("fig9", "**Fig. 9 (temporal stability)**: %s, 60 frames of frame 20's view with fresh noise, "
                        "temporal error mean_p |L_t - L_{t-1}| of tone-mapped luminance over frames 31-60.\n\n" % a.size +
                        table(["scene", "config", "temporal error", "reflective", "reflective / Ours"], rows)))

        # Figs. 12-13: reflection MVs against brute force.
        rows = []
        for scene in (["corridor", "corridorglossy"] if "motion" in only else []):
            out = os.path.join(tmp, scene)
            run([cli, "render", "--scene", scene, "--size", a.size, "--frames", a.motion_frames, "-o", out,
                 "--no-reference-cache"])
            for r in lines_json(run([exp, "--experiment", "motion", "--input", out])):
                rows.append([scene, "on" if r["ldspScaling"] else "off", r["reference"], "%.3f" % r["meanError"],
                             "%.3f - %.3f" % (r["minFrameError"], r["maxFrameError"]),
                             "%.1f %%" % (100 * r["withinOnePixel"]), "%.1f" % r["meanTaps"]])
        if rows: sections.append(("fig12", "**Figs. 12-13 (reflection motion vectors)**: %s, the first %s frames of "
                        "the corridor flythrough past a mirror orb (corridor) and a glossy orb (roughness 0.2), diamond search against the 200x200 "
                        "brute-force search with the same subpixel step (`rtdenoise eval --reflection-motion`); reference "
                        "*ray*: its glossy distance to the far representative ray's half-line, *line*: Eq. 5 as written "
                        "(`--line-reference`), see \"Eq. 5, ray or line\".\n\n"
                        % (a.size, a.motion_frames) + table(["scene", "LDSP scaling", "reference", "mean error (px)", "per-frame range",
                                          "within 1 px", "taps / pixel"], rows)))

        # Fig. 11: supersampling with guide rays.
        rows = []
        for label, scene in ([("mirrorfloor", "mirrorfloor"), ("corridorglossy", "corridorglossy")]
                             if "supersampling" in only else []):
            for r in lines_json(run([exp, "--experiment", "supersampling", "--scene", scene, "--frames", "16",
                                     "--eval-frames", "2", "--spp", "4", "--reference-spp", "256"] + size)):
                rows.append([label, r["config"], "%.4f" % r["rmse"], "%.4f" % r["ssim"]])
        if rows: sections.append(("fig11", "**Fig. 11 (supersampling)**: %s, 16 frames, scored on the last 2 against 256-spp "
                        "*jittered* (anti-aliased) references; Ours in every row.\n\n" % a.size +
                        table(["scene", "config", "RMSE", "SSIM"], rows)))

        if "cost" in only:
            seq = os.path.join(tmp, "mirrorfloor720")
            # 12 frames: the first timed frames' histories are past the spatial-variance bound (4)
            run([cli, "render", "--scene", "mirrorfloor", "--size", "1280x720", "--frames", "12", "-o", seq,
                 "--no-reference-cache"])
            passes = {}
            for rep in range(3):  # alternate, medians of medians
                for variant in ["voorhuisBase", "voorhuis"]:
                    j = os.path.join(tmp, "bench-%s-%d.json" % (variant, rep))
                    run([cli, "bench", "--input", seq, "--frames", "6", "--warmup", "5",
                         "--set", "variant=" + variant, "--json", j])
                    with open(j) as f:
                        d = json.load(f)
                    passes.setdefault(variant, []).append(d)
            def med(v):
                v = sorted(v)
                return v[len(v) // 2]
            names = []
            for variant in ["voorhuisBase", "voorhuis"]:
                for d in passes[variant]:
                    for n in d["passesMedianMs"]:
                        if n not in names:
                            names.append(n)
            rows = []
            for n in names:
                vals = [med([d["passesMedianMs"].get(n, 0.0) for d in passes[v]]) for v in ["voorhuisBase", "voorhuis"]]
                rows.append([n, "%.2f" % vals[0], "%.2f" % vals[1]])
            tb, to = (med([d["totalMedianMs"] for d in passes[v]]) for v in ["voorhuisBase", "voorhuis"])
            rows.append(["**total**", "%.1f" % tb, "%.1f" % to])
            sections.append(("fig14", "**Fig. 14 (cost over Base)**: `rtdenoise bench --input` on 12 rendered 1280x720 "
                            "mirrorfloor frames (frames 6-11 timed, histories of 6 frames and more), CPU, 2 threads, medians of 3 "
                            "alternating runs, on " + machine + "; "
                            "Ours costs %.1f ms (%.0f %%) over Base.\n\n" % (to - tb, 100 * (to - tb) / tb) +
                            table(["pass", "Base (ms)", "Ours (ms)"], rows)))
            out = run([bench, "--benchmark_filter=BM_GuideRays", "--benchmark_format=json", "--benchmark_repetitions=3",
                       "--benchmark_report_aggregates_only=true"])
            bj = json.loads(out)
            rows = []
            for b in bj["benchmarks"]:
                if b.get("aggregate_name") == "median":
                    spp = re.search(r"/(\d+)", b["run_name"]).group(1)
                    rows.append([spp, "%.1f" % b["real_time"]])
            sections.append(("fig15", "**Fig. 15 (guide-ray cost)**: `rtd_bench --benchmark_filter=BM_GuideRays`, 1280x720, on " + machine + ", "
                            "assignment + Eq. 7 pre-mix + copy back (the filter runs at guide resolution, so its cost "
                            "does not change with spp), medians of 3.\n\n" + table(["spp", "ms per frame"], rows)))



if __name__ == "__main__":
    main()
