#!/usr/bin/env bash
# Writes the man page rtdenoise.1 from the command's own --help texts with help2man: the main
# help, then one section per subcommand with its options, then the exit status. Run by the
# build (apps/CMakeLists.txt); usage: tools/make_manpage.sh PATH/TO/rtdenoise OUT.1
set -euo pipefail
cli="$1"
out="$2"
include="$(mktemp)"
trap 'rm -f "$include"' EXIT
subcommands=$("$cli" --help | awk '/^Subcommands:/ {on = 1; next} on && !NF {exit} on {print $1}')
{
  echo "[SUBCOMMANDS]"
  for s in $subcommands; do
    echo ".SS $s"
    echo ".nf"
    # Drop the footer (it becomes EXIT STATUS) and escape roff's backslashes and leading dots.
    "$cli" "$s" --help | grep -v '^Exit status:' | sed -e 's/\\/\\e/g' -e 's/^\./\\\&./'
    echo ".fi"
  done
  echo "[EXIT STATUS]"
  echo "0 success; 1 bad input data or files (the message names the file, frame and channel);"
  echo "2 usage error (unknown or meaningless option, bad value); 3 internal error."
  echo "[SEE ALSO]"
  echo "docs/cli.md, docs/sequence-format.md and docs/evaluation.md in the rtdenoise sources."
} > "$include"
help2man --no-info --no-discard-stderr --section=1 --name="real-time denoisers for 1-spp path-traced sequences" \
  --include="$include" --output="$out.tmp" "$cli"
mv "$out.tmp" "$out"
