#ifndef SOFTBENCH_MODEL_ACTUATOR_MODEL_H_
#define SOFTBENCH_MODEL_ACTUATOR_MODEL_H_

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace softbench {

// The four fitted constants of the axial-shear model (thesis section 3.3) and
// the natural length used by the variable-moment-arm variant. The defaults are
// the thesis's fitted values (model.md, "Constants fitted in the thesis").
struct ActuatorConstants {
  // A_z: axial effective area [mm^2] (Eq. 2.5).
  double axial_area_mm2 = 157.0;
  // W_y: shear effective-area factor, A_y = W_y * theta [mm^2/rad] (Eq. 2.7).
  double shear_area_factor_mm2_per_rad = 105.2;
  // k_s: linear stiffness [N/mm] (Eq. 2.8).
  double linear_stiffness_n_per_mm = 2.71;
  // k_theta: torsional factor k_t / L_m [N/rad] (Eq. 2.14 / 2.15).
  double torsional_factor_n_per_rad = 19.31;
  // L0: natural length of the soft portion [mm] (Eq. 3.3).
  double natural_length_mm = 18.5;

  // Empty when every constant is finite and physically meaningful; otherwise a
  // sentence naming the offending constant.
  std::optional<std::string> Problem() const;
};

// How the static-offset terms resolve the deformation into axial and shear
// components.
enum class AngleTerms {
  // cos(theta) ~ 1, sin(theta) ~ theta: Eq. 2.14 / 2.15, the thesis's choice.
  kSmallAngle,
  // Exact trigonometric resolution: Eq. 3.1 / 3.2.
  kTrigonometric,
};

// Whether the torsional moment arm changes with the actuator's length.
enum class MomentArm {
  kConstant,
  // k_theta(dL) = k_theta0 / (1 + dL / L0): Eq. 3.3.
  kVariable,
};

// A force model is data: constants plus the choice of terms. Every variant of
// the thesis, and the pressurized-spring baseline of [26], is one value of this
// struct; the only branch on the variant is in ActuatorForce().
struct ForceModel {
  ActuatorConstants constants;
  AngleTerms angle_terms = AngleTerms::kSmallAngle;
  MomentArm moment_arm = MomentArm::kConstant;

  // The thesis's default: small angles, constant moment arm (Eq. 2.16 / 2.17).
  static ForceModel SmallAngle(const ActuatorConstants& constants);
  // Eq. 3.1 / 3.2 in place of the small-angle static offsets.
  static ForceModel FullTrigonometric(const ActuatorConstants& constants);
  // Eq. 3.3: small angles with a length-dependent torsional factor.
  static ForceModel VariableMomentArm(const ActuatorConstants& constants);
  // The previous work's pressurized spring [26]: the small-angle model with
  // k_theta = 0 and W_y = 0 (thesis 4.1.3).
  static ForceModel PressurizedSpring(const ActuatorConstants& constants);
};

// The axial-shear model's variants by the names used on the command line, in
// YAML files and in reports: the one list every parser, help text and message
// uses.
struct ModelVariant {
  std::string_view name;
  ForceModel (*make)(const ActuatorConstants& constants);
};
std::span<const ModelVariant> ModelVariants();
// "small-angle, full-trig or variable-arm", for help texts and errors.
std::string ModelVariantNames();

std::string_view VariantName(const ForceModel& model);
// The variant called `name` with `constants`; nullopt for any other name.
std::optional<ForceModel> ForceModelFromVariantName(
    std::string_view name, const ActuatorConstants& constants);

// The actuator's deformation: change of length and orientation angle
// (model.md, "One actuator").
struct Deformation {
  double delta_length_mm = 0.0;
  double theta_rad = 0.0;
};

// The force an actuator exerts on its head, in its local (y, z) frame, and its
// partial derivatives. Vectors are ordered (F_y, F_z).
struct ActuatorForce {
  Eigen::Vector2d force_in_local_n = Eigen::Vector2d::Zero();
  Eigen::Vector2d d_force_d_delta_length = Eigen::Vector2d::Zero();  // [N/mm]
  Eigen::Vector2d d_force_d_theta = Eigen::Vector2d::Zero();         // [N/rad]
  Eigen::Vector2d d_force_d_pressure = Eigen::Vector2d::Zero();      // [N/MPa]
};

// Evaluates Eq. 2.16 / 2.17 (or the variant's equations) at pressure P [MPa].
ActuatorForce EvaluateActuatorForce(const ForceModel& model,
                                    double pressure_mpa,
                                    const Deformation& deformation);

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_ACTUATOR_MODEL_H_
