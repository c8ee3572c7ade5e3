#ifndef SOFTBENCH_PIPELINES_FORMATS_PREDICTION_TABLE_H_
#define SOFTBENCH_PIPELINES_FORMATS_PREDICTION_TABLE_H_

#include <Eigen/Core>
#include <string>

#include "model/equilibrium.h"
#include "model/mechanism.h"

namespace softbench {

// The CSV written by `predict` and `workspace` (README, command-line
// contract): p1_UNIT..pN_UNIT, then y1_mm,z1_mm per head in the mechanism's
// head order, then converged (0/1), residual_n, in_range (0 where a
// pressure or an actuator's deformation lies beyond the range the constants
// were characterised over: the model extrapolates there) and within_reach
// (0 where the predicted position lies beyond every position that pressures
// in the characterised range reach, or could not be shown to lie within it).
// Positions of a configuration that did not converge are written as nan,
// never as numbers.
class PredictionTable {
 public:
  // `pressure_unit` names the pressure columns' unit (p1_psi).
  PredictionTable(const Mechanism& mechanism, std::string_view pressure_unit);

  // Pressures are written in the caller's unit, as given.
  void AddRow(const Eigen::VectorXd& pressures_in_unit,
              const Eigen::VectorXd& displacements_mm,
              const EquilibriumSummary& summary, bool in_range,
              bool within_reach);
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_PREDICTION_TABLE_H_
