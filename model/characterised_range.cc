#include "model/characterised_range.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace softbench {

std::optional<std::string> CharacterisedRange::Problem() const {
  for (const double limit :
       {max_pressure_mpa, max_abs_delta_length_mm, max_abs_theta_rad}) {
    if (!(limit > 0.0) || !std::isfinite(limit)) {
      return "the characterised range's limits must be finite and > 0";
    }
  }
  return std::nullopt;
}

std::optional<std::string> PressuresOutsideCharacterisedRange(
    const CharacterisedRange& range, const Eigen::VectorXd& pressures_mpa) {
  for (int k = 0; k < pressures_mpa.size(); ++k) {
    if (pressures_mpa[k] > range.max_pressure_mpa * (1.0 + 1e-9)) {
      std::ostringstream why;
      why.precision(3);
      why << "p" << k + 1 << " = " << pressures_mpa[k]
          << " MPa is above the characterised " << range.max_pressure_mpa
          << " MPa";
      return why.str();
    }
  }
  return std::nullopt;
}

std::optional<std::string> OutsideCharacterisedRange(
    const CharacterisedRange& range, const EquilibriumProblem& problem,
    const Eigen::VectorXd& pressures_mpa, const Eigen::VectorXd& x) {
  if (std::optional<std::string> why =
          PressuresOutsideCharacterisedRange(range, pressures_mpa)) {
    return why;
  }
  std::ostringstream why;
  why.precision(3);
  const std::vector<Deformation> deformations = problem.Deformations(x);
  for (size_t a = 0; a < deformations.size(); ++a) {
    const Deformation& d = deformations[a];
    if (std::abs(d.delta_length_mm) > range.max_abs_delta_length_mm) {
      why << "actuator " << a + 1 << " stretches by " << d.delta_length_mm
          << " mm, beyond the characterised +-" << range.max_abs_delta_length_mm
          << " mm";
      return why.str();
    }
    if (std::abs(d.theta_rad) > range.max_abs_theta_rad) {
      why << "actuator " << a + 1 << " bends by " << RadToDeg(d.theta_rad)
          << " deg, beyond the characterised +-"
          << RadToDeg(range.max_abs_theta_rad) << " deg";
      return why.str();
    }
  }
  return std::nullopt;
}

}  // namespace softbench
