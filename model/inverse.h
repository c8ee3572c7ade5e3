#ifndef SOFTBENCH_MODEL_INVERSE_H_
#define SOFTBENCH_MODEL_INVERSE_H_

#include <Eigen/Core>
#include <optional>
#include <string>

#include "model/characterised_range.h"
#include "model/equilibrium.h"
#include "model/units.h"

namespace softbench {

struct InverseOptions {
  // Upper pressure bound per actuator [MPa]; the lower bound is 0 (the thesis
  // applies positive pressures only). Default: 6 psi, the thesis's range.
  double max_pressure_mpa = 6.0 * kMpaPerPsi;
  // The target counts as reached when the equilibrium at the found pressures
  // is within this distance of it [mm].
  double reach_tolerance_mm = 1e-6;
  // Weight of |P / P_max|^2 next to the squared position error [mm^2]. Where
  // several pressure sets reach the target it selects the one of least norm
  // (the minimum-pressure solution); it is small enough that the position it
  // costs is far below reach_tolerance_mm.
  double pressure_weight = 1e-12;
  // Ceres iterations per start.
  int max_iterations = 200;
  EquilibriumOptions equilibrium;

  std::optional<std::string> Problem() const;
};

struct InverseResult {
  // True when pressures in [0, max_pressure_mpa] place every head at the
  // target within reach_tolerance_mm.
  bool reachable = false;
  // The pressures found [MPa]: reaching the target, or, when unreachable,
  // producing the closest reachable configuration.
  Eigen::VectorXd pressures_mpa;
  // The equilibrium at `pressures_mpa` (y1, z1, y2, z2, ...) [mm]: the target
  // itself when reachable, the closest reachable point otherwise.
  Eigen::VectorXd displacements_mm;
  // Euclidean distance between displacements_mm and the target [mm].
  double distance_mm = 0.0;
  // Why the search ended, for people; says so when the optimiser failed.
  std::string message;
  // False when no start produced a usable solution (every start failed).
  bool solved = false;
};

// Finds pressures in [0, max_pressure_mpa] whose equilibrium puts the heads at
// `target_mm` (y1, z1, ...; one pair per head). Bounded least squares (Ceres)
// on the position error, with the derivative of the equilibrium with respect
// to the pressures from the implicit function theorem:
//   dx/dP = -(dR/dx)^-1 dR/dP.
// Several starts guard against local minima of the closest-point problem.
InverseResult SolvePressuresForTarget(const EquilibriumProblem& problem,
                                      const Eigen::VectorXd& target_mm,
                                      const InverseOptions& options = {});

// Whether a prediction lies within the mechanism's reach: the head positions
// that pressures in [0, max_pressure_mpa] (the characterised range) hold the
// heads at. Pressures beyond that range can put the model's heads anywhere
// (1000 psi moves the delta's head 133 mm); such a prediction is marked,
// never shown as fine.
struct ReachCheck {
  // True when some pressures in range put the heads within tolerance_mm of
  // the prediction.
  bool within = true;
  // Distance from the prediction to the closest position in reach [mm]; nan
  // when the search found no equilibrium (then `within` is false: the
  // prediction cannot be shown to lie in reach).
  double distance_mm = 0.0;
};
// `x_mm` holds the heads' predicted displacements (y1, z1, ...). Solves the
// bounded inverse (SolvePressuresForTarget), so call it only for pressures
// beyond the range: within it, a prediction is in reach by definition.
ReachCheck CheckWithinReach(const EquilibriumProblem& problem,
                            const Eigen::VectorXd& x_mm,
                            double max_pressure_mpa,
                            double tolerance_mm = 1e-3);

// The reach of the equilibrium `x_mm` found at `pressures_mpa`: within by
// definition when the pressures lie in `range` (deformations beyond it are
// extrapolation, which in_range marks, but the pressures do reach there);
// else CheckWithinReach against the range's highest pressure.
ReachCheck ReachOfPrediction(const EquilibriumProblem& problem,
                             const CharacterisedRange& range,
                             const Eigen::VectorXd& pressures_mpa,
                             const Eigen::VectorXd& x_mm);

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_INVERSE_H_
