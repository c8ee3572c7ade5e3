// `softbench fit` end to end, from the CSV logs on disk to constants and
// goodness of fit for every model (docs/benchmarks.md, "Characterisation").
// Usage: fit_benchmark [benchmark flags] -- MANIFEST.yaml
// (bench/run_fit_bench.sh makes the 24-million-row protocol first.)
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <iostream>

#include "pipelines/characterisation/fit_analysis.h"

namespace {

void BM_FitFromCsv(benchmark::State& state, const std::string& manifest) {
  softbench::FitAnalysisOptions options;
  options.input_path = manifest;
  options.progress = false;
  int64_t rows = 0;
  for (auto _ : state) {
    const softbench::FitRun run = softbench::RunFitAnalysis(options);
    rows = run.read.rows;
    benchmark::DoNotOptimize(run.fits.data());
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["rows"] = static_cast<double>(rows);
  state.counters["rows_per_s"] = benchmark::Counter(
      static_cast<double>(rows), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["peak_rss_mb"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (argc != 2) {
    std::cerr << "usage: fit_benchmark [benchmark flags] MANIFEST.yaml\n";
    return 2;
  }
  benchmark::RegisterBenchmark("BM_FitFromCsv", BM_FitFromCsv, argv[1])
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
