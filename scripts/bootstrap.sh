#!/usr/bin/env bash
# Installs, with apt-get, exactly the Debian 12 packages softbench needs that
# are missing; running it again installs nothing. `--bench` adds what the
# benchmark peers under bench/peers/ need (Python with SciPy and OpenCV,
# hyperfine).
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev libceres-dev libyaml-cpp-dev libcli11-dev
  libfmt-dev libspdlog-dev libfast-float-dev
  libopencv-dev libapriltag-dev
  libavformat-dev libavcodec-dev libavutil-dev libswscale-dev
  libgtest-dev libbenchmark-dev
)
if [[ "${1:-}" == "--bench" ]]; then
  packages+=(python3 python3-numpy python3-scipy python3-opencv hyperfine ffmpeg)
fi

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$package")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

sudo=()
if [[ $(id -u) -ne 0 ]]; then sudo=(sudo); fi
echo "bootstrap: installing ${missing[*]}" >&2
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq \
  --no-install-recommends "${missing[@]}" >&2
