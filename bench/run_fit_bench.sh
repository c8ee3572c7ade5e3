#!/usr/bin/env bash
# Characterisation benchmark: `softbench fit` on the thesis's full protocol
# (54 tests, 24 million rows at 5.7 kHz, ~1.5 GB of CSV) against the
# NumPy/SciPy peer on the same files, and peak memory at a tenth of the rows
# (docs/benchmarks.md). Usage: bench/run_fit_bench.sh [repetitions] (def. 5)
set -euo pipefail
cd "$(dirname "$0")/.."
repetitions=${1:-5}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null
softbench=./build/release/softbench
for rate in 5700 570; do
  dir=build/bench-forces-$rate
  if [[ ! -f $dir/manifest.yaml ]]; then
    $softbench -q synth-forces --out "$dir" --rate "$rate" --seed 1
  fi
done
full=build/bench-forces-5700/manifest.yaml

echo "== softbench fit (Google Benchmark, median of $repetitions) =="
./build/release/bench/fit_benchmark --benchmark_repetitions="$repetitions" \
  --benchmark_report_aggregates_only=true "$full" | grep -E 'median|^Run'

echo "== peak memory of the whole command: a tenth of the rows, then all =="
for rate in 570 5700; do
  /usr/bin/time -f "rate $rate Hz: %e s, peak %M KB" \
    $softbench -q fit build/bench-forces-$rate/manifest.yaml | head -1
done

echo "== peer: pandas + scipy.linalg.lstsq, same files =="
/usr/bin/python3 bench/peers/fit_numpy.py "$full" --repeats 3
