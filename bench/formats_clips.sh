# Sourced by bench/run_formats_bench.sh and bench/run_memory_4k_bench.sh.
#
# render_formats_clip NAME RENDER-OPTIONS... renders build/bench-formats/NAME.mp4
# once (with NAME.truth.csv and NAME.plan.yaml) from the same 16 s scene of
# the delta mechanism (bench/formats.plan.yaml, a still camera, seed 29),
# and leaves an existing one as it is.
formats_clips=build/bench-formats

render_formats_clip() {
  local name=$1
  shift
  mkdir -p "$formats_clips"
  if [[ ! -f "$formats_clips/$name.mp4" ]]; then
    echo "rendering $formats_clips/$name.mp4 (a few minutes on 2 cores)..."
    ./build/release/softbench --quiet render --plan bench/formats.plan.yaml \
      --out "$formats_clips/$name.mp4" \
      --truth "$formats_clips/$name.truth.csv" \
      --plan-out "$formats_clips/$name.plan.yaml" --preset veryfast \
      --seed 29 "$@"
  fi
}
