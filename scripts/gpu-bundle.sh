#!/usr/bin/env bash
# Packs the release build's CLI and the shared libraries it loads (its ldd closure, glibc left
# out) into .devbundle/rtd.tar.xz, with .devbundle/run.sh, so that scripts/bench-gpu.sh's
# measurements run on a GPU machine that lacks Debian's packages (the device tool's NVIDIA
# machines run Ubuntu 24.04: glibc 2.39 runs the Debian 12 build). On that machine, from a
# copy of the repository's root holding .devbundle (and, where the machine has no Vulkan
# loader, Debian's libvulkan1 and libglvnd .debs in .gl, unpacked first):
# `bash .devbundle/run.sh`; the figures go to $OUT (or ./gpu-out). docs/performance.md,
# "Vulkan backend", has the first H200 figures it gave.
set -euo pipefail
cd "$(dirname "$0")/.."
cli=build/release/apps/rtdenoise
[ -x "$cli" ] || { echo "build first: cmake --preset release && cmake --build build/release" >&2; exit 2; }
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib" .devbundle
cp "$cli" "$stage/bin/"
libs=$(find build/release/src -name 'librtdenoise*.so.0' | sort)  # not the OpenImageIO module: the benchmark reads no image files
for f in $( (ldd "$cli"; for s in $libs; do ldd "$s"; done) | awk '$3 ~ /^\// {print $3}' | sort -u) $libs; do
  case $(basename "$f") in libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|librt.so.*|ld-linux*) ;; *) cp -L "$f" "$stage/lib/" ;; esac
done
tar -C "$stage" -cf - . | xz -T0 -6 > .devbundle/rtd.tar.xz
cat > .devbundle/run.sh <<'RUN'
#!/bin/bash
# Made by scripts/gpu-bundle.sh: scripts/bench-gpu.sh with the carried bundle's CLI.
set -o pipefail
out=${OUT:-gpu-out}; mkdir -p "$out"
if [ -d .gl ]; then for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig; fi
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f $icd ] && export VK_DRIVER_FILES=$icd
mkdir -p /tmp/rtd && tar -xJf .devbundle/rtd.tar.xz -C /tmp/rtd
export LD_LIBRARY_PATH=/tmp/rtd/lib
{
  head -2 /etc/os-release
  RTD_CLI=/tmp/rtd/bin/rtdenoise bash scripts/bench-gpu.sh
} 2>&1 | tee "$out/bench.txt"
RUN
chmod +x .devbundle/run.sh
ls -l .devbundle
