#!/usr/bin/env bash
# Opens a softbench HTML report in headless Chromium (Debian's chromium) and
# checks that the page logs nothing to its console and draws every chart as
# SVG. Usage: report/check_in_chromium.sh REPORT.html [SCREENSHOT.png]
# Exit 0: clean; 1: console messages or missing charts (printed); 2: usage.
set -uo pipefail
report=${1:?usage: check_in_chromium.sh REPORT.html [SCREENSHOT.png]}
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# The flags keep Chromium off the (closed) network and out of first-run work.
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run
  --disable-background-networking --disable-component-update --disable-sync
  --user-data-dir="$profile" --virtual-time-budget=30000)
url="file://$(realpath "$report")"
dom=$(chromium "${flags[@]}" --enable-logging=stderr --v=0 --dump-dom "$url" \
  2>"$profile/stderr.log")
console=$(grep -F ':CONSOLE' "$profile/stderr.log" || true)
charts=$(grep -o "vegaEmbed('#chart" "$report" | wc -l)
drawn=$(grep -o '<svg[^>]*class="marks"' <<<"$dom" | wc -l)
if [[ -n "${2:-}" ]]; then
  chromium "${flags[@]}" --window-size=1200,2400 --screenshot="$2" "$url" \
    >/dev/null 2>&1
fi
status=0
if [[ -n "$console" ]]; then
  echo "console messages:"; echo "$console"; status=1
fi
if [[ "$drawn" -ne "$charts" || "$charts" -eq 0 ]]; then
  echo "charts drawn: $drawn of $charts"; status=1
fi
echo "$charts charts, $drawn drawn, console ${console:+not }clean"
exit $status
