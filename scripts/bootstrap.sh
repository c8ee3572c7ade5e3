#!/usr/bin/env bash
# Installs, with apt-get, exactly the Debian 12 packages softbench needs that
# are missing; running it again installs nothing. `--bench` adds what the
# benchmark peers under bench/peers/ need (Python with SciPy and OpenCV,
# hyperfine).
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev libceres-dev libyaml-cpp-dev libcli11-dev
  libboost-dev         # Boost.Math's chi-squared test (validate's lift correction)
  libfmt-dev libspdlog-dev libfast-float-dev
  libopencv-dev libapriltag-dev
  libssl-dev           # SHA-256 of every input a report names (OpenSSL)
  libheif-dev          # tune reads HEIC photos (an iPhone's default)
  libcairo2-dev        # softbench targets: the printable sheets (PDF, SVG)
  libpoppler-cpp-dev   # the tests rasterise those sheets to measure them
  opencv-doc           # the tests calibrate on its chessboard photos left*.jpg
  libavformat-dev libavcodec-dev libavutil-dev libswscale-dev
  libgtest-dev libgmock-dev libbenchmark-dev nlohmann-json3-dev
  chromium  # the tests open every HTML report in it (report/check_in_chromium.sh)
  python3   # .ci/check_layers.py, run by the tests
  clang libclang-rt-14-dev  # the fuzz preset: libFuzzer with ASan and UBSan
  clang-format clang-tidy   # the lint preset (.ci/lint.py)
)
# Node.js and npm install the report's plotting libraries and ESLint
# (report/); any Node.js >= 18.18 will do, so an existing one (e.g.
# NodeSource's) is kept.
if ! command -v npm >/dev/null 2>&1; then packages+=(nodejs npm); fi
if [[ "${1:-}" == "--bench" ]]; then
  packages+=(python3-numpy python3-scipy python3-pandas python3-yaml
    python3-opencv hyperfine ffmpeg)
fi

# The report assets: Vega, Vega-Lite and vega-embed at the versions of
# report/package-lock.json, inlined into every HTML report (never fetched at
# build or run time). Installed once; again only when the lock file changes.
install_report_assets() {
  local report
  report="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/report"
  if ! cmp -s "$report/package-lock.json" \
      "$report/node_modules/.softbench-installed-lock" 2>/dev/null; then
    echo "bootstrap: installing report assets with npm" >&2
    (cd "$report" && npm ci --no-audit --no-fund --loglevel=error >&2)
    cp "$report/package-lock.json" \
      "$report/node_modules/.softbench-installed-lock"
  fi
}

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$package")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  install_report_assets
  exit 0
fi

sudo=()
if [[ $(id -u) -ne 0 ]]; then sudo=(sudo); fi
echo "bootstrap: installing ${missing[*]}" >&2
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq \
  --no-install-recommends "${missing[@]}" >&2
install_report_assets
