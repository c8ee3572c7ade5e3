#include "model/actuator_model.h"

#include <cmath>
#include <vector>

#include "util/join_names.h"

namespace softbench {

std::optional<std::string> ActuatorConstants::Problem() const {
  const auto finite_non_negative = [](double value) {
    return std::isfinite(value) && value >= 0.0;
  };
  if (!finite_non_negative(axial_area_mm2)) {
    return "axial area A_z must be a finite number >= 0 mm^2";
  }
  if (!finite_non_negative(shear_area_factor_mm2_per_rad)) {
    return "shear area factor W_y must be a finite number >= 0 mm^2/rad";
  }
  if (!std::isfinite(linear_stiffness_n_per_mm) ||
      linear_stiffness_n_per_mm <= 0.0) {
    return "linear stiffness k_s must be a finite number > 0 N/mm";
  }
  if (!finite_non_negative(torsional_factor_n_per_rad)) {
    return "torsional factor k_theta must be a finite number >= 0 N/rad";
  }
  if (!std::isfinite(natural_length_mm) || natural_length_mm <= 0.0) {
    return "natural length L0 must be a finite number > 0 mm";
  }
  return std::nullopt;
}

ForceModel ForceModel::SmallAngle(const ActuatorConstants& constants) {
  return {constants, AngleTerms::kSmallAngle, MomentArm::kConstant};
}

ForceModel ForceModel::FullTrigonometric(const ActuatorConstants& constants) {
  return {constants, AngleTerms::kTrigonometric, MomentArm::kConstant};
}

ForceModel ForceModel::VariableMomentArm(const ActuatorConstants& constants) {
  return {constants, AngleTerms::kSmallAngle, MomentArm::kVariable};
}

ForceModel ForceModel::PressurizedSpring(const ActuatorConstants& constants) {
  ActuatorConstants spring = constants;
  spring.torsional_factor_n_per_rad = 0.0;
  spring.shear_area_factor_mm2_per_rad = 0.0;
  return SmallAngle(spring);
}

std::string_view VariantName(const ForceModel& model) {
  if (model.moment_arm == MomentArm::kVariable) return "variable-arm";
  if (model.angle_terms == AngleTerms::kTrigonometric) return "full-trig";
  return "small-angle";
}

std::span<const ModelVariant> ModelVariants() {
  static constexpr ModelVariant kVariants[] = {
      {"small-angle", &ForceModel::SmallAngle},
      {"full-trig", &ForceModel::FullTrigonometric},
      {"variable-arm", &ForceModel::VariableMomentArm}};
  return kVariants;
}

std::string ModelVariantNames() {
  std::vector<std::string_view> names;
  for (const ModelVariant& v : ModelVariants()) names.push_back(v.name);
  return JoinNames(names);
}

std::optional<ForceModel> ForceModelFromVariantName(
    std::string_view name, const ActuatorConstants& constants) {
  for (const ModelVariant& v : ModelVariants()) {
    if (v.name == name) return v.make(constants);
  }
  return std::nullopt;
}

ActuatorForce EvaluateActuatorForce(const ForceModel& model,
                                    double pressure_mpa,
                                    const Deformation& deformation) {
  const ActuatorConstants& constants = model.constants;
  const double dl = deformation.delta_length_mm;
  const double theta = deformation.theta_rad;

  // All variants share one form (Eq. 2.12 / 2.13 with P terms of Eq. 2.16):
  //   F_z =  P A_z      - k_s dL c(theta) + k(dL) theta s(theta)
  //   F_y = -P W_y theta + k_s dL s(theta) + k(dL) theta c(theta)
  // with (c, s) = (1, theta) for small angles, (cos, sin) otherwise.
  double c = 1.0, s = theta, dc = 0.0,
         ds = 1.0;  // c(theta), s(theta), derivatives
  if (model.angle_terms == AngleTerms::kTrigonometric) {
    c = std::cos(theta);
    s = std::sin(theta);
    dc = -s;
    ds = c;
  }
  double k = constants.torsional_factor_n_per_rad, dk = 0.0;
  if (model.moment_arm == MomentArm::kVariable) {
    const double stretch = 1.0 + dl / constants.natural_length_mm;  // Eq. 3.3
    k = constants.torsional_factor_n_per_rad / stretch;
    dk = -k / (stretch * constants.natural_length_mm);
  }
  const double ks = constants.linear_stiffness_n_per_mm;
  const double wy = constants.shear_area_factor_mm2_per_rad;

  ActuatorForce out;
  out.force_in_local_n = {
      -pressure_mpa * wy * theta + ks * dl * s + k * theta * c,
      pressure_mpa * constants.axial_area_mm2 - ks * dl * c + k * theta * s};
  out.d_force_d_delta_length = {ks * s + dk * theta * c,
                                -ks * c + dk * theta * s};
  out.d_force_d_theta = {
      -pressure_mpa * wy + ks * dl * ds + k * (c + theta * dc),
      -ks * dl * dc + k * (s + theta * ds)};
  out.d_force_d_pressure = {-wy * theta, constants.axial_area_mm2};
  return out;
}

}  // namespace softbench
