// Model benchmarks (issue: foundation): one delta solve, the 343-point delta
// map and the 3125-point floating map. Run with bench/run_model_bench.sh,
// which also runs the SciPy peer on the same map.
#include <benchmark/benchmark.h>

#include <cmath>

#include "model/units.h"
#include "model/workspace.h"
#include "pipelines/formats/mechanism_io.h"

namespace softbench {
namespace {

WorkspaceOptions PsiLevels(double max_psi, double step_psi, int threads) {
  WorkspaceOptions options;
  options.pressure_levels_mpa = EvenPressureLevels(
      max_psi * kMpaPerPsi, static_cast<int>(std::lround(max_psi / step_psi)));
  options.num_threads = threads;
  return options;
}

void BM_DeltaSolve(benchmark::State& state) {
  const EquilibriumProblem problem(LoadMechanism("delta"),
                                   ForceModel::SmallAngle({}));
  EquilibriumSolver solver(problem);
  const Eigen::Vector3d pressures = Eigen::Vector3d(6, 6, 0) * kMpaPerPsi;
  for (auto _ : state) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2);  // cold start from rest
    benchmark::DoNotOptimize(solver.Solve(pressures, &x));
    benchmark::DoNotOptimize(x.data());
  }
}
BENCHMARK(BM_DeltaSolve);

// `reuse`: each map goes into the previous one's storage, as a caller sweeping
// many maps does; otherwise into fresh storage (first touch of its memory).
void BM_Map(benchmark::State& state, const char* mechanism, double step_psi,
            bool reuse) {
  const EquilibriumProblem problem(LoadMechanism(mechanism),
                                   ForceModel::SmallAngle({}));
  const WorkspaceOptions options =
      PsiLevels(6.0, step_psi, static_cast<int>(state.range(0)));
  int64_t points = 0, iterations = 0;
  WorkspaceMap map;
  for (auto _ : state) {
    if (!reuse) map = WorkspaceMap();
    ComputeWorkspace(problem, options, &map);
    if (map.num_not_converged != 0) state.SkipWithError("not converged");
    points = map.pressures_mpa.rows();
    iterations = 0;
    for (const EquilibriumSummary& s : map.summaries)
      iterations += s.iterations;
    benchmark::DoNotOptimize(map.displacements_mm.data());
  }
  state.counters["points"] = static_cast<double>(points);
  state.counters["newton_per_solve"] =
      static_cast<double>(iterations) / static_cast<double>(points);
  state.counters["solves_per_s"] =
      benchmark::Counter(static_cast<double>(points),
                         benchmark::Counter::kIsIterationInvariantRate);
}
// Argument: worker threads (0 = all cores).
BENCHMARK_CAPTURE(BM_Map, Delta343, "delta", 1.0, true)
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Map, Floating3125, "floating", 1.5, true)
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Map, Floating3125_fresh_storage, "floating", 1.5, false)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace softbench

BENCHMARK_MAIN();
