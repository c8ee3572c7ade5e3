#ifndef SOFTBENCH_MODEL_PREDICTION_H_
#define SOFTBENCH_MODEL_PREDICTION_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "model/characterised_range.h"
#include "model/equilibrium.h"
#include "model/inverse.h"

namespace softbench {

// What the model says of one configuration of pressures (`softbench
// predict`): the equilibrium, whether the constants were characterised
// there, and whether the bench can hold the heads there at all.
struct Prediction {
  // The heads' displacements (y1, z1, ...) [mm]; zero when not converged.
  Eigen::VectorXd x;
  EquilibriumSummary summary;
  // Why the configuration lies beyond the characterised range (the model
  // extrapolates there), or nullopt.
  std::optional<std::string> outside_range;
  // Whether pressures within the range reach the prediction
  // (ReachOfPrediction); {false, nan} when there is no equilibrium.
  ReachCheck reach;
};

// The model's prediction for each row of pressures [MPa]. Rows are often
// neighbours (a sweep, a test plan's steps), so each solve starts from the
// previous solution and falls back to the rest state.
std::vector<Prediction> PredictEquilibria(
    const EquilibriumProblem& problem, const CharacterisedRange& range,
    const std::vector<Eigen::VectorXd>& pressures_mpa,
    const EquilibriumOptions& options = {});

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_PREDICTION_H_
