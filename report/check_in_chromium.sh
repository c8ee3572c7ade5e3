#!/usr/bin/env bash
# Opens a softbench HTML report in headless Chromium (Debian's chromium) as a
# desktop browser, as a phone (390 px wide) and in print emulation, and checks
# that the page logs nothing to its console and draws every chart as SVG in
# each. Usage: report/check_in_chromium.sh REPORT.html [SCREENSHOT.png]
# With a screenshot path it also writes SCREENSHOT-phone.png (390 px wide)
# and SCREENSHOT-print.pdf (the page as printed).
# Exit 0: clean; 1: console messages, missing charts or no print (printed);
# 2: usage.
set -uo pipefail
report=${1:?usage: check_in_chromium.sh REPORT.html [SCREENSHOT.png]}
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# The flags keep Chromium off the (closed) network and out of first-run work.
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run
  --disable-background-networking --disable-component-update --disable-sync
  --user-data-dir="$profile" --virtual-time-budget=30000)
url="file://$(realpath "$report")"
charts=$(grep -o "vegaEmbed('#chart" "$report" | wc -l)
status=0

# One view of the page: its DOM after the scripts ran, its console, and the
# charts drawn in it. $1 names the view; the rest are extra flags.
check_view() {
  local view=$1
  shift
  local dom console drawn
  dom=$(chromium "${flags[@]}" "$@" --enable-logging=stderr --v=0 \
    --dump-dom "$url" 2>"$profile/stderr.log")
  console=$(grep -F ':CONSOLE' "$profile/stderr.log" || true)
  drawn=$(grep -o '<svg[^>]*class="marks"' <<<"$dom" | wc -l)
  if [[ -n "$console" ]]; then
    echo "$view: console messages:"; echo "$console"; status=1
  fi
  if [[ "$drawn" -ne "$charts" ]]; then
    echo "$view: charts drawn: $drawn of $charts"; status=1
  fi
  echo "$view: $charts charts, $drawn drawn, console ${console:+not }clean"
}

check_view desktop --window-size=1200,2400
check_view phone --window-size=390,844
# Print emulation: the page printed to PDF, with its console checked.
pdf="$profile/print.pdf"
chromium "${flags[@]}" --enable-logging=stderr --v=0 --no-pdf-header-footer \
  --print-to-pdf="$pdf" "$url" >/dev/null 2>"$profile/print.log"
console=$(grep -F ':CONSOLE' "$profile/print.log" || true)
if [[ ! -s "$pdf" ]] || ! head -c 5 "$pdf" | grep -q '%PDF-'; then
  echo "print: no PDF"; status=1
elif [[ -n "$console" ]]; then
  echo "print: console messages:"; echo "$console"; status=1
else
  pages=$(grep -a -o '/Count [0-9]*' "$pdf" | head -1 | cut -d' ' -f2)
  echo "print: ${pages:-?} pages, console clean"
fi
if [[ $charts -eq 0 ]]; then
  echo "no charts in the page"; status=1
fi

if [[ -n "${2:-}" ]]; then
  chromium "${flags[@]}" --window-size=1200,2400 --screenshot="$2" "$url" \
    >/dev/null 2>&1
  chromium "${flags[@]}" --window-size=390,2400 --hide-scrollbars \
    --screenshot="${2%.png}-phone.png" "$url" >/dev/null 2>&1
  cp "$pdf" "${2%.png}-print.pdf"
fi
exit $status
