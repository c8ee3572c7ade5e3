# Sourced by the footage scripts, with their arguments: enters the
# repository's root, sets `root` and `softbench` (the release build, which
# must be there) and render_and_validate (below), takes the one argument
# OUT_DIR, makes it and enters it.
# shellcheck shell=bash
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$PWD
softbench=$root/build/release/softbench
[[ -x $softbench ]] || { echo "build first: cmake --build --preset release" >&2; exit 2; }
[[ $# -eq 1 ]] || { echo "usage: $0 OUT_DIR" >&2; exit 2; }
mkdir -p "$1"
cd "$1"

# Renders ./plan.yaml into NAME/ (video.mp4, truth.csv, rendered.plan.yaml)
# with render's FLAGs and seed 21, and validates it into NAME/report: each
# case of the footage scripts.
#   render_and_validate NAME [FLAG...]
render_and_validate() {
  local name=$1
  shift
  mkdir -p "$name"
  "$softbench" --quiet render --plan plan.yaml --out "$name/video.mp4" \
    --truth "$name/truth.csv" --plan-out "$name/rendered.plan.yaml" \
    --seed 21 "$@" >/dev/null
  "$softbench" --quiet validate --plan "$name/rendered.plan.yaml" \
    "$name/video.mp4" --out "$name/report" >/dev/null
}
