# Sourced by the footage scripts, with their arguments: enters the
# repository's root, sets `root` and `softbench` (the release build, which
# must be there), takes the one argument OUT_DIR, makes it and enters it.
# shellcheck shell=bash
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$PWD
softbench=$root/build/release/softbench
[[ -x $softbench ]] || { echo "build first: cmake --build --preset release" >&2; exit 2; }
[[ $# -eq 1 ]] || { echo "usage: $0 OUT_DIR" >&2; exit 2; }
mkdir -p "$1"
cd "$1"
