#!/usr/bin/env bash
# What registering every frame to the bench costs: softbench validate on the
# phone sample (samples/phone: 1080p H.264 at 10 Mb/s, 16.5 s, a camera that
# moves), with and without registration, against decoding the same file and
# nothing else (docs/benchmarks.md, "Registration"):
#   decode only          ffmpeg -f null (default threads), the limit
#   validate             every frame registered and measured, full report
#   no registration      validate --no-registration (the camera taken still)
# Usage: bench/run_registration_bench.sh [rounds]   (default 7; medians)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/interleaved_rounds.sh
runs=${1:-7}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null

video=samples/phone/phone.mp4
out=build/bench-registration
mkdir -p "$out"
validate="./build/release/softbench --quiet validate $video --plan samples/phone/rendered.plan.yaml"
commands=("ffmpeg -v error -i $video -map 0:v -f null -"
  "$validate --out $out/registered"
  "$validate --no-registration --out $out/still")
run_rounds "$runs" "$out/times.txt" "${commands[@]}"
python3 - "$out/times.txt" <<'PY'
import statistics, sys
rounds = [list(map(float, line.split()[1:])) for line in open(sys.argv[1])]
decode, registered, still = (statistics.median(r[k] for r in rounds) for k in range(3))
print(f"decode only (ffmpeg -f null)   median {decode:6.3f} s")
print(f"validate, registered           median {registered:6.3f} s")
print(f"validate --no-registration     median {still:6.3f} s")
print(f"registered / decode only:      {statistics.median(r[1] / r[0] for r in rounds):.3f}"
      f"  (median of {len(rounds)} rounds; target <= 1.15)")
print(f"registered / not registered:   {statistics.median(r[1] / r[2] for r in rounds):.3f}")
PY
