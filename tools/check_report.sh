#!/bin/sh
# Loads an rtdenoise HTML report in headless Chromium and saves a screenshot, so a person (or CI)
# can see that it renders. Usage: tools/check_report.sh REPORT.html [SCREENSHOT.png] [WIDTHxHEIGHT]
# Needs Debian's `chromium` (apt-get install chromium). Exits non-zero if Chromium fails or
# writes no screenshot.
set -eu
report=$(realpath "$1")
shot=${2:-${report%.html}.png}
size=${3:-1400x1000}
chromium=${CHROMIUM:-/usr/bin/chromium}
[ -x "$chromium" ] || { echo "check_report: $chromium not found (apt-get install chromium)" >&2; exit 2; }
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
rm -f "$shot"
timeout 120 "$chromium" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$profile" --screenshot="$(realpath -m "$shot")" --window-size="$(echo "$size" | tr x ,)" \
  "file://$report" >"$profile/log.txt" 2>&1 || { cat "$profile/log.txt" >&2; exit 1; }
[ -s "$shot" ] || { echo "check_report: no screenshot written" >&2; cat "$profile/log.txt" >&2; exit 1; }
echo "screenshot: $shot"
