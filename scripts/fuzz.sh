#!/usr/bin/env bash
# Runs every libFuzzer target (fuzz/README.md) of a sanitizer build, starting from the committed
# seeds and regression inputs. Fails on a crash, a sanitizer report (ASan, UBSan, a leak), a
# single allocation over 1 GiB (-malloc_limit_mb), more than 2 GiB resident (-rss_limit_mb) or
# an input that takes over 10 s (-timeout). Usage: scripts/fuzz.sh [build dir] (default
# build/asan). Two modes:
# - default (CI): a fixed number of mutations per target with a fixed seed (-seed=1, -runs=N
#   below, about 15-20 s each on a 2-vCPU machine), from an empty working corpus, so every run
#   explores nearly the same inputs (not exactly: the library's threads make coverage, and so
#   the corpus, vary a little). RTD_FUZZ_RUNS multiplies the counts (0: seeds and regression
#   inputs only, no mutation).
# - RTD_FUZZ_SECONDS=S: S seconds per target with a random seed, keeping the working corpus
#   between runs: exploration, by hand.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/asan}
seconds=${RTD_FUZZ_SECONDS:-0}
scale=${RTD_FUZZ_RUNS:-1}
work=$build/fuzz-work
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-/usr/lib/llvm-14/bin/llvm-symbolizer}

status=0
# Mutations per target in the default mode (their speeds differ: settings denoises two frames
# per input).
declare -A runs=([native_sequence]=4000 [blender_sequence]=4000 [per_buffer]=3000 [sequence_json]=4000 [settings]=600)
for t in native_sequence blender_sequence per_buffer sequence_json settings; do
  dir=$work/$t
  rm -rf "$dir/seeds" && mkdir -p "$dir/corpus" "$dir/seeds"
  # Seeds: fuzz/corpus/<target>, the regression fixtures tests/fixtures/fuzz/<target>, and the
  # Blender fixture's frames for the two EXR readers.
  for seeds in fuzz/corpus/"$t" tests/fixtures/fuzz/"$t"; do
    if [ -d "$seeds" ]; then cp "$seeds"/* "$dir/seeds/"; fi
  done
  case $t in native_sequence|blender_sequence) cp tests/fixtures/blender/*.exr "$dir/seeds/" ;; esac
  if [ "$seconds" != 0 ]; then mode=(-max_total_time="$seconds"); echo "fuzz_$t: ${seconds} s"
  else
    rm -rf "$dir/corpus" && mkdir -p "$dir/corpus"
    n=$(( ${runs[$t]} * scale ))
    mode=(-seed=1 -runs="$n"); echo "fuzz_$t: $n runs, seed 1"
  fi
  if ! "$build/fuzz/fuzz_$t" "${mode[@]}" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
       -max_len=131072 -print_final_stats=1 -artifact_prefix="$dir/" "$dir/corpus" "$dir/seeds" \
       > "$dir/log.txt" 2>&1; then
    echo "fuzz_$t FAILED (inputs and log in $dir):"
    tail -n 60 "$dir/log.txt"
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$dir/log.txt" | tr '\n' ' '
    echo
  fi
done
exit $status
