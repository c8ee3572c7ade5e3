#include "model/prediction.h"

#include <limits>

namespace softbench {

std::vector<Prediction> PredictEquilibria(
    const EquilibriumProblem& problem, const CharacterisedRange& range,
    const std::vector<Eigen::VectorXd>& pressures_mpa,
    const EquilibriumOptions& options) {
  EquilibriumSolver solver(problem, options);
  std::vector<Prediction> predictions;
  predictions.reserve(pressures_mpa.size());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
  for (const Eigen::VectorXd& pressures : pressures_mpa) {
    Prediction& p = predictions.emplace_back();
    p.summary = solver.Solve(pressures, &x);
    if (!p.summary.converged()) {
      x.setZero();
      p.summary = solver.Solve(pressures, &x);
    }
    if (!p.summary.converged()) x.setZero();
    p.x = x;
    if (p.summary.converged()) {
      p.outside_range = OutsideCharacterisedRange(range, problem, pressures, x);
      // Only pressures beyond the range can carry the heads out of reach.
      p.reach = ReachOfPrediction(problem, range, pressures, x);
    } else {
      p.outside_range = PressuresOutsideCharacterisedRange(range, pressures);
      p.reach = {false, std::numeric_limits<double>::quiet_NaN()};
    }
  }
  return predictions;
}

}  // namespace softbench
