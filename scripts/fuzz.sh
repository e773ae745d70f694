#!/usr/bin/env bash
# Runs every libFuzzer target (fuzz/README.md) of a sanitizer build for a fixed time each,
# starting from the committed seeds. Fails on a crash, a sanitizer report (ASan, UBSan, a leak),
# a single allocation over 1 GiB (-malloc_limit_mb), more than 2 GiB resident (-rss_limit_mb) or
# an input that takes over 10 s (-timeout). Usage: scripts/fuzz.sh [build dir] (default
# build/asan); RTD_FUZZ_SECONDS per target (default 20). RTD_FUZZ_SECONDS=0 runs each target over
# its seeds and regression inputs only, once, with no mutation: deterministic (what CI runs while
# the open findings of fuzz/findings/ are not fixed, docs/input-validation.md).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/asan}
seconds=${RTD_FUZZ_SECONDS:-20}
work=$build/fuzz-work
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-/usr/lib/llvm-14/bin/llvm-symbolizer}

status=0
for t in native_sequence blender_sequence per_buffer sequence_json settings; do
  dir=$work/$t
  mkdir -p "$dir/corpus" "$dir/seeds"
  # Seeds: fuzz/corpus/<target>, the regression fixtures tests/fixtures/fuzz/<target>, and the
  # Blender fixture's frames for the two EXR readers.
  for seeds in fuzz/corpus/"$t" tests/fixtures/fuzz/"$t"; do
    if [ -d "$seeds" ]; then cp "$seeds"/* "$dir/seeds/"; fi
  done
  case $t in native_sequence|blender_sequence) cp tests/fixtures/blender/*.exr "$dir/seeds/" ;; esac
  if [ "$seconds" = 0 ]; then mode=(-runs=0); echo "fuzz_$t: seeds only"
  else mode=(-max_total_time="$seconds"); echo "fuzz_$t: ${seconds} s"; fi
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
