"""Summarises the compare runs of tools/eval/compare_learned.sh as Markdown: per scene the SSIM
of the last frame and the mean SSIM over all frames for each method (the input too), then the
median milliseconds per frame. Standard library only."""
import json
import os
import sys


def main(root):
    rows, times = {}, {}
    scenes = sorted(d for d in os.listdir(root) if not d.endswith("-tnnd-accumulate"))
    for scene in scenes:
        for sub, suffix in ((scene, ""), (scene + "-tnnd-accumulate", " + accumulate")):
            path = os.path.join(root, sub, "metrics.json")
            if not os.path.exists(path):
                continue
            with open(path) as f:
                doc = json.load(f)
            for run in doc["runs"]:
                label = run["label"] + suffix
                if suffix and not run["method"]:
                    continue  # the input, already listed
                ssim = [fr["ssim"] for fr in run["frames"]]
                rows.setdefault(label, {})[scene] = (ssim[-1], sum(ssim) / len(ssim))
                if run["method"]:
                    times.setdefault(label, []).append(run["medianTotalMs"])
    print("| method | " + " | ".join(scenes) + " | ms / frame |")
    print("|---|" + "---|" * (len(scenes) + 1))
    for label, per in rows.items():
        cells = [f"{per[s][0]:.3f} ({per[s][1]:.3f})" if s in per else "" for s in scenes]
        t = times.get(label)
        print(f"| {label} | " + " | ".join(cells) + f" | {sorted(t)[len(t) // 2]:.1f} |" if t else f"| {label} | " + " | ".join(cells) + " | |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "build/eval/learned")
