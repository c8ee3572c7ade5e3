#!/usr/bin/env bash
# Model benchmarks side by side with the SciPy peer (docs/benchmarks.md).
# Usage: bench/run_model_bench.sh [repetitions]   (default 10)
set -euo pipefail
cd "$(dirname "$0")/.."
repetitions=${1:-10}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null

echo "== softbench (Google Benchmark, median of $repetitions) =="
./build/release/bench/model_benchmark --benchmark_repetitions="$repetitions" \
  --benchmark_report_aggregates_only=true | grep -E 'median|^Run|CPU|Load'

echo "== peer: Python + SciPy fsolve, floating map =="
/usr/bin/python3 bench/peers/floating_map_scipy.py --repeats 3
