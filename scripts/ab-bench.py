#!/usr/bin/env python3
"""A/B of two builds of librtdenoise, or of two settings, on a shared, noisy machine (docs/performance.md).

The current build's programs run alternately with the baseline's library and with their own
(LD_LIBRARY_PATH), round after round, so that a change of the host's load hits both sides
alike; the report is each side's median over the rounds of the per-run medians, and the ratio.
With --baseline-set instead, both sides run the current build and the baseline side adds those
settings (a setting's cost, measured the same way).

  scripts/ab-bench.py --baseline /tmp/base-build svgf --set variant=dundr
  scripts/ab-bench.py --baseline /tmp/base-build --path avx2 --rounds 5 bmfr
  scripts/ab-bench.py --baseline /tmp/base-build --benchmark 'BM_Reproject/path:[12]'
  scripts/ab-bench.py --baseline-set taaHistoryFilter=catmullRom svgf --set variant=dundr

--baseline is a build directory of the baseline (its src/librtdenoise.so.0 is used) or a
directory holding a librtdenoise.so.0. Make one with `git worktree add /tmp/base <commit>` and
`cmake --preset release -B /tmp/base-build -S /tmp/base && cmake --build /tmp/base-build`, or by
copying build/release/src/librtdenoise.so.0.1.0 to DIR/librtdenoise.so.0 before rebuilding.
Both sides run the current build's CLI or rtd_bench, a client of the public API: a change to
that API needs both sides built in full instead.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def library_dir(path):
    for candidate in (os.path.join(path, "src"), path):
        if os.path.exists(os.path.join(candidate, "librtdenoise.so.0")):
            return candidate
    sys.exit(f"ab-bench: no librtdenoise.so.0 in {path} or {path}/src")


def run(cmd, libdir, cpu_path):
    env = dict(os.environ)
    if libdir:
        env["LD_LIBRARY_PATH"] = libdir + (":" + env["LD_LIBRARY_PATH"] if env.get("LD_LIBRARY_PATH") else "")
    if cpu_path:
        env["RTD_CPU_PATH"] = cpu_path
    done = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if done.returncode:
        sys.exit(f"ab-bench: {' '.join(cmd)} failed ({done.returncode}):\n{done.stderr[-2000:]}")
    return done.stdout


def check_loaded(program, libdir):
    """Stops unless `program` run with libdir first on the library path loads libdir's
    librtdenoise.so.0 (a DT_RPATH would win over LD_LIBRARY_PATH and compare the current build
    with itself)."""
    env = dict(os.environ, LD_LIBRARY_PATH=libdir)
    out = subprocess.run(["ldd", program], env=env, stdout=subprocess.PIPE, text=True).stdout
    loaded = [line.split("=>")[1].split()[0] for line in out.splitlines() if "librtdenoise.so.0 =>" in line]
    if not loaded or os.path.realpath(os.path.dirname(loaded[0])) != os.path.realpath(libdir):
        sys.exit(f"ab-bench: {program} loads {loaded[0] if loaded else 'no librtdenoise.so.0'}, not {libdir}'s")


def pipeline_round(args, libdir, settings=()):
    """{name: ms} for one `rtdenoise bench` run: every pass and the total (medians over frames);
    `settings`: key=value pairs given after the run's own (--baseline-set)."""
    sets = [a for kv in settings for a in ("--set", kv)]
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        run([args.cli, "bench", "--method", args.method, *args.extra, *sets, "--size", args.size, "--threads",
             str(args.threads), "--frames", str(args.frames), "--warmup", str(args.warmup), "--json", out.name],
            libdir, args.path)
        report = json.load(open(out.name))
    figures = dict(report["passesMedianMs"])
    figures["total"] = report["totalMedianMs"]
    return figures, report.get("cpuPath", "?")


def benchmark_round(args, libdir, settings=()):
    """{benchmark: ms} for one rtd_bench run (the median of its repetitions, real time);
    `settings` is always empty here (main refuses --baseline-set with --benchmark)."""
    text = run([args.rtd_bench, f"--benchmark_filter={args.benchmark}", "--benchmark_repetitions=3",
                "--benchmark_report_aggregates_only=true", "--benchmark_format=json"], libdir, args.path)
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
    return {b["run_name"]: b["real_time"] * scale[b["time_unit"]]
            for b in json.loads(text)["benchmarks"] if b.get("aggregate_name") == "median"}, args.path or "default"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0], epilog=__doc__.split("\n", 2)[2],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--baseline", help="baseline build directory, or a directory with librtdenoise.so.0")
    p.add_argument("--baseline-set", action="append", default=[], metavar="KEY=VALUE",
                   help="instead of --baseline: the current build on both sides, the baseline side with this setting "
                        "(repeatable)")
    p.add_argument("--rounds", type=int, default=3, help="alternations (default 3)")
    p.add_argument("--path", help="RTD_CPU_PATH for both sides (sse2, avx2, avx512)")
    p.add_argument("--size", default="1280x720")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--frames", type=int, default=12)
    p.add_argument("--warmup", type=int, default=4)
    p.add_argument("--benchmark", help="an rtd_bench --benchmark_filter instead of the pipeline")
    p.add_argument("--statistic", choices=("median", "min"), default="median",
                   help="per side over the rounds (default median); min where the host's load only adds time "
                        "and comes and goes within the run")
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"), help="the current build")
    p.add_argument("method", nargs="?", help="rtdenoise bench --method")
    p.add_argument("extra", nargs=argparse.REMAINDER, help="more rtdenoise bench options (--set k=v ...)")
    args = p.parse_args()
    if not args.benchmark and not args.method:
        p.error("a method or --benchmark")
    if bool(args.baseline) == bool(args.baseline_set):
        p.error("either --baseline (two builds) or --baseline-set (two settings)")
    if args.baseline_set and args.benchmark:
        p.error("--baseline-set compares settings of `rtdenoise bench`, not rtd_bench benchmarks")
    args.cli = os.path.join(args.build, "apps", "rtdenoise")
    args.rtd_bench = os.path.join(args.build, "bench", "rtd_bench")
    base = library_dir(args.baseline) if args.baseline else None
    one_round = benchmark_round if args.benchmark else pipeline_round
    if base:
        check_loaded(args.rtd_bench if args.benchmark else args.cli, base)

    runs = {"baseline": [], "current": []}
    for r in range(args.rounds):
        for side, libdir in (("baseline", base), ("current", None)):
            figures, cpu_path = one_round(args, libdir, args.baseline_set if side == "baseline" else ())
            runs[side].append(figures)
        key = "total" if not args.benchmark else next(iter(runs["current"][-1]))
        print(f"round {r + 1}/{args.rounds}: {key} baseline {runs['baseline'][-1].get(key, float('nan')):.2f}, "
              f"current {runs['current'][-1][key]:.2f} ms", file=sys.stderr)

    what = args.benchmark or " ".join([args.method, *args.extra])
    if args.baseline_set:
        what += f" (baseline: + {' '.join(args.baseline_set)})"
    print(f"{what}: {args.rounds} alternations, CPU path {cpu_path}, {args.statistic}s over the rounds (ms)")
    # Every figure of either side: a pass that one build merged into another or split shows
    # on its own side only ("-" on the other).
    names = sorted(set().union(*runs["baseline"], *runs["current"]), key=lambda n: (n == "total", n))

    def median(side, name):
        values = [f[name] for f in runs[side] if name in f]
        if not values:
            return None
        return min(values) if args.statistic == "min" else statistics.median(values)

    print(f"| {'figure':<44} | baseline | current | current / baseline |")
    print(f"|{'-' * 46}|----------|---------|--------------------|")
    for name in names:
        b, c = median("baseline", name), median("current", name)
        cell = lambda v, width: f"{v:{width}.2f}" if v is not None else f"{'-':>{width}}"
        ratio = f"{c / b:18.3f}" if b and c is not None else f"{'-':>18}"
        print(f"| {name:<44} | {cell(b, 8)} | {cell(c, 7)} | {ratio} |")


if __name__ == "__main__":
    main()
