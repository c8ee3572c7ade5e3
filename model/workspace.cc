#include "model/workspace.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "model/inverse.h"
#include "util/check.h"

namespace softbench {
namespace {

// A base-`radix` counter over the actuators' level indices (most significant
// first) and its reflected (boustrophedon) Gray code: a digit is mirrored when
// the counter digits above it sum to an odd number, so consecutive codes
// differ by one level of one actuator.
class GrayCounter {
 public:
  GrayCounter(int64_t start, int radix, int num_digits)
      : radix_(radix), counter_(num_digits), gray_(num_digits) {
    for (int i = num_digits - 1; i >= 0; --i, start /= radix) {
      counter_[i] = static_cast<int>(start % radix);
    }
    UpdateGray();
  }
  const std::vector<int>& digits() const { return gray_; }
  void Increment() {
    for (int i = static_cast<int>(counter_.size()) - 1; i >= 0; --i) {
      if (++counter_[i] < radix_) break;
      counter_[i] = 0;
    }
    UpdateGray();
  }
  // Row of the current configuration in lexicographic order of its levels.
  int64_t LexicographicIndex() const {
    int64_t index = 0;
    for (int d : gray_) index = index * radix_ + d;
    return index;
  }

 private:
  void UpdateGray() {
    int higher_sum = 0;
    for (size_t i = 0; i < counter_.size(); ++i) {
      gray_[i] = higher_sum % 2 == 1 ? radix_ - 1 - counter_[i] : counter_[i];
      higher_sum += counter_[i];
    }
  }

  int radix_;
  std::vector<int> counter_, gray_;
};

// Configurations per run of the Gray-code order that one thread solves in
// sequence (see ComputeWorkspace).
constexpr int64_t kRunLength = 128;

}  // namespace

std::vector<double> EvenPressureLevels(double max_mpa, int num_intervals) {
  SOFTBENCH_CHECK(num_intervals >= 0) << num_intervals;
  if (num_intervals == 0) return {0.0};
  std::vector<double> levels;
  for (int i = 0; i <= num_intervals; ++i) {
    levels.push_back(max_mpa * i / num_intervals);
  }
  return levels;
}

std::optional<std::string> WorkspaceOptions::Problem() const {
  if (pressure_levels_mpa.empty()) return "no pressure levels given";
  for (double level : pressure_levels_mpa) {
    if (!std::isfinite(level) || level < 0.0) {
      return "pressure levels must be finite and >= 0";
    }
  }
  if (num_threads < 0) return "num_threads must be >= 0";
  return equilibrium.Problem();
}

std::vector<HeadExtents> WorkspaceMap::Extents() const {
  const int num_heads = static_cast<int>(displacements_mm.cols()) / 2;
  std::vector<HeadExtents> extents(num_heads);
  bool first = true;
  for (int i = 0; i < displacements_mm.rows(); ++i) {
    if (!summaries[i].converged()) continue;
    for (int h = 0; h < num_heads; ++h) {
      const Eigen::Vector2d p = displacements_mm.row(i).segment<2>(2 * h);
      extents[h].min_mm = first ? p : extents[h].min_mm.cwiseMin(p);
      extents[h].max_mm = first ? p : extents[h].max_mm.cwiseMax(p);
    }
    first = false;
  }
  return extents;
}

WorkspaceMap ComputeWorkspace(const EquilibriumProblem& problem,
                              const WorkspaceOptions& options) {
  WorkspaceMap map;
  ComputeWorkspace(problem, options, &map);
  return map;
}

void ComputeWorkspace(const EquilibriumProblem& problem,
                      const WorkspaceOptions& options, WorkspaceMap* map_out) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  const int radix = static_cast<int>(options.pressure_levels_mpa.size());
  const int num_actuators = problem.NumActuators();
  const int n = problem.NumUnknowns();
  int64_t count = 1;
  for (int i = 0; i < num_actuators; ++i) count *= radix;

  WorkspaceMap& map = *map_out;
  map.pressures_mpa.resize(count, num_actuators);
  map.displacements_mm.resize(count, n);
  map.summaries.resize(count);
  map.in_range.assign(count, 1);
  map.within_reach.assign(count, 1);

  // The Gray-code order is cut into runs of a fixed length that threads take
  // one at a time: a thread that starts late or shares its core with other
  // work takes fewer runs instead of holding everyone up, and the map does
  // not depend on the number of threads. Each run starts from rest; longer
  // runs would spend fewer cold starts but balance the threads worse.
  const int64_t num_runs = (count + kRunLength - 1) / kRunLength;
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  const int num_threads = static_cast<int>(std::min<int64_t>(
      num_runs,
      options.num_threads > 0 ? options.num_threads : std::max(1, hardware)));
  const auto solve_run = [&](int64_t begin, int64_t end) {
    EquilibriumSolver solver(problem, options.equilibrium);
    GrayCounter gray(begin, radix, num_actuators);
    Eigen::VectorXd pressures(num_actuators);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n), warm_start(n);
    for (int64_t g = begin; g < end; ++g, gray.Increment()) {
      for (int a = 0; a < num_actuators; ++a) {
        pressures[a] = options.pressure_levels_mpa[gray.digits()[a]];
      }
      warm_start = x;
      solver.PredictSolution(pressures, &x);
      EquilibriumSummary summary = solver.Solve(pressures, &x);
      if (!summary.converged()) {
        x.setZero();
        summary = solver.Solve(pressures, &x);
        if (!summary.converged()) x = warm_start;
      }
      const int64_t row = gray.LexicographicIndex();
      map.pressures_mpa.row(row) = pressures.transpose();
      if (summary.converged()) {
        map.displacements_mm.row(row) = x.transpose();
        if (options.range &&
            OutsideCharacterisedRange(*options.range, problem, pressures, x)) {
          map.in_range[row] = 0;
        }
        if (options.range &&
            !ReachOfPrediction(problem, *options.range, pressures, x).within) {
          map.within_reach[row] = 0;
        }
      } else {
        map.within_reach[row] = 0;
        map.displacements_mm.row(row).setConstant(std::nan(""));
        if (options.range &&
            PressuresOutsideCharacterisedRange(*options.range, pressures)) {
          map.in_range[row] = 0;
        }
      }
      map.summaries[row] = summary;
    }
  };

  std::atomic<int64_t> next_run{0};
  const auto take_runs = [&] {
    for (int64_t run; (run = next_run.fetch_add(1)) < num_runs;) {
      solve_run(run * kRunLength, std::min(count, (run + 1) * kRunLength));
    }
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < num_threads; ++t) workers.emplace_back(take_runs);
  take_runs();
  for (std::thread& worker : workers) worker.join();
  map.num_not_converged = static_cast<int>(std::count_if(
      map.summaries.begin(), map.summaries.end(),
      [](const EquilibriumSummary& s) { return !s.converged(); }));
  map.num_outside_range = static_cast<int>(
      std::count(map.in_range.begin(), map.in_range.end(), uint8_t{0}));
  map.num_beyond_reach = 0;
  for (int64_t i = 0; i < count; ++i) {
    if (map.summaries[i].converged() && map.within_reach[i] == 0) {
      ++map.num_beyond_reach;
    }
  }
}

}  // namespace softbench
