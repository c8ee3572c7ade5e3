#ifndef SOFTBENCH_MODEL_CHARACTERISED_RANGE_H_
#define SOFTBENCH_MODEL_CHARACTERISED_RANGE_H_

#include <Eigen/Core>
#include <optional>
#include <string>

#include "model/equilibrium.h"
#include "model/units.h"

namespace softbench {

// The range the actuator constants were characterised over: inside it the
// model interpolates its fit, outside it extrapolates, and a prediction
// there is marked, never silently given as if it were as good. The
// defaults are the thesis's characterisation protocol (chapter 3): pressures up
// to the regulator's 6 psi, dL from -3 to 3 mm, theta up to 30 degrees.
struct CharacterisedRange {
  double max_pressure_mpa = 6.0 * kMpaPerPsi;
  double max_abs_delta_length_mm = 3.0;
  double max_abs_theta_rad = DegToRad(30.0);

  // Empty when every limit is finite and > 0; else names the limit.
  std::optional<std::string> Problem() const;
};

// Why `pressures_mpa` lie outside `range` (the first pressure above it), or
// nothing. Needs no equilibrium: it marks a configuration that did not
// converge too.
std::optional<std::string> PressuresOutsideCharacterisedRange(
    const CharacterisedRange& range, const Eigen::VectorXd& pressures_mpa);

// Why a configuration lies outside `range` (the first pressure or actuator
// deformation beyond it, e.g. "p2 = 0.069 MPa is above the characterised
// 0.041 MPa"), or nothing when it lies inside. `x` holds the heads'
// displacements at equilibrium [mm] for `pressures_mpa`.
std::optional<std::string> OutsideCharacterisedRange(
    const CharacterisedRange& range, const EquilibriumProblem& problem,
    const Eigen::VectorXd& pressures_mpa, const Eigen::VectorXd& x);

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_CHARACTERISED_RANGE_H_
