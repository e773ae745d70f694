#!/usr/bin/env bash
# Makes the seeds of fuzz_per_buffer (fuzz/corpus/per_buffer): one small colour image per format
# the target tries (8x6 RGB noise, float where the format allows, 8- and 16-bit integers
# otherwise), each prefixed by the byte that selects its format (the index in the target's
# kExtensions). Needs oiiotool (Debian: openimageio-tools).
set -euo pipefail
cd "$(dirname "$0")"
out=corpus/per_buffer
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
make() {  # index, extension, oiiotool output options, seed name
  oiiotool --pattern noise:type=uniform:min=0:max=2:seed=7 8x6 3 -d "$3" -o "$tmp/img.$2"
  { printf "\\x$(printf %02x "$1")"; cat "$tmp/img.$2"; } > "$out/$4"
}
make 0 exr half exr_half
make 0 exr float exr_float
# OpenImageIO 2.4 reads PFM but has no PFM writer: written here (header, then little-endian
# floats, bottom row first): a constant 3.0.
{ printf '\x01PF\n8 6\n-1.0\n'; head -c $((8 * 6 * 3 * 4)) /dev/zero | tr '\0' '\100'; } > "$out/pfm"
make 2 hdr float hdr
make 3 png uint8 png
make 4 tif float tif_float
make 4 tif uint16 tif_16bit
