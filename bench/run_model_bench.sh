#!/usr/bin/env bash
# Model benchmarks side by side with the SciPy peer (docs/benchmarks.md).
# Usage: bench/run_model_bench.sh [rounds]   (default 5)
# Each round runs model_benchmark (5 repetitions, medians) and then the peer
# once on the same floating map, so a change in the shared host's load hits
# both alike; the ratio is taken within each round, and its median printed.
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null

out=build/bench-model
mkdir -p "$out"
ratios=()
for round in $(seq "$rounds"); do
  ./build/release/bench/model_benchmark --benchmark_repetitions=5 \
    --benchmark_report_aggregates_only=true --benchmark_format=json \
    --benchmark_out="$out/round$round.json" >/dev/null
  peer_s=$(/usr/bin/python3 bench/peers/floating_map_scipy.py --repeats 1 \
    2>/dev/null | awk '/^median_s/ {print $2}')
  line=$(python3 - "$out/round$round.json" "$peer_s" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
median = {r["run_name"]: r for r in runs if r["aggregate_name"] == "median"}
unit = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
def seconds(name):
    r = median[name]
    return r["real_time"] * unit[r["time_unit"]]
def short(name):
    return name.replace("BM_Map/", "").replace("BM_", "").replace("/real_time", "")
parts = [f"{short(n)} {seconds(n) * 1e6:.2f} us" for n in median]
ours = seconds("BM_Map/Floating3125/0/real_time")
peer = float(sys.argv[2])
print(f"{ours * 1e3:.3f} {peer:.3f} {peer / ours:.0f} | " + ", ".join(parts))
PY
)
  read -r ours_ms peer_s ratio rest <<<"$line"
  echo "round $round: floating map (all cores) $ours_ms ms, SciPy $peer_s s," \
    "ratio ${ratio}x ${rest}"
  ratios+=("$ratio")
done
median=$(printf '%s\n' "${ratios[@]}" | sort -g |
  awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}')
echo "median ratio over $rounds rounds: ${median}x (target: >= 1000x)"
