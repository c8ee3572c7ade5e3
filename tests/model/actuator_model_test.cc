#include "model/actuator_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace softbench {
namespace {

std::vector<ForceModel> AllVariants() {
  const ActuatorConstants c;
  return {ForceModel::SmallAngle(c), ForceModel::FullTrigonometric(c),
          ForceModel::VariableMomentArm(c), ForceModel::PressurizedSpring(c)};
}

TEST(ActuatorForce, SmallAngleIsEquation216And217) {
  const ActuatorConstants c;
  const double p = 0.03, dl = 1.2, theta = 0.2;
  const ActuatorForce f =
      EvaluateActuatorForce(ForceModel::SmallAngle(c), p, {dl, theta});
  // F_z = P A_z - k_s dL + k_theta theta^2 (Eq. 2.16).
  EXPECT_NEAR(f.force_in_local_n.y(),
              p * 157.0 - 2.71 * dl + 19.31 * theta * theta, 1e-12);
  // F_y = -P W_y theta + k_s dL theta + k_theta theta (Eq. 2.17).
  EXPECT_NEAR(f.force_in_local_n.x(),
              -p * 105.2 * theta + 2.71 * dl * theta + 19.31 * theta, 1e-12);
}

TEST(ActuatorForce, FullTrigonometricIsEquation31And32) {
  const ActuatorConstants c;
  const double p = 0.02, dl = -0.7, theta = 0.45;
  const ActuatorForce f =
      EvaluateActuatorForce(ForceModel::FullTrigonometric(c), p, {dl, theta});
  EXPECT_NEAR(
      f.force_in_local_n.y(),
      p * 157.0 - 2.71 * dl * std::cos(theta) + 19.31 * theta * std::sin(theta),
      1e-12);
  EXPECT_NEAR(f.force_in_local_n.x(),
              -p * 105.2 * theta + 2.71 * dl * std::sin(theta) +
                  19.31 * theta * std::cos(theta),
              1e-12);
}

TEST(ActuatorForce, VariableArmScalesTorsionalFactorByEquation33) {
  const ActuatorConstants c;
  const double dl = 1.5, theta = 0.3;
  const ActuatorForce variable =
      EvaluateActuatorForce(ForceModel::VariableMomentArm(c), 0.0, {dl, theta});
  ActuatorConstants scaled = c;
  scaled.torsional_factor_n_per_rad /= 1.0 + dl / c.natural_length_mm;
  const ActuatorForce constant =
      EvaluateActuatorForce(ForceModel::SmallAngle(scaled), 0.0, {dl, theta});
  EXPECT_NEAR((variable.force_in_local_n - constant.force_in_local_n).norm(),
              0.0, 1e-12);
}

TEST(ActuatorForce, IsZeroAtRestWithoutPressure) {
  for (const ForceModel& model : AllVariants()) {
    EXPECT_EQ(EvaluateActuatorForce(model, 0.0, {}).force_in_local_n.norm(),
              0.0);
  }
}

TEST(ActuatorForce, DerivativesMatchCentralDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pressure(0.0, 0.05);
  std::uniform_real_distribution<double> length(-3.0, 3.0);
  std::uniform_real_distribution<double> angle(-0.6, 0.6);
  const double h = 1e-6;
  for (const ForceModel& model : AllVariants()) {
    for (int trial = 0; trial < 50; ++trial) {
      const double p = pressure(rng), dl = length(rng), theta = angle(rng);
      const ActuatorForce f = EvaluateActuatorForce(model, p, {dl, theta});
      const auto force = [&](double pp, double ll, double tt) {
        return EvaluateActuatorForce(model, pp, {ll, tt}).force_in_local_n;
      };
      const Eigen::Vector2d d_length =
          (force(p, dl + h, theta) - force(p, dl - h, theta)) / (2 * h);
      const Eigen::Vector2d d_theta =
          (force(p, dl, theta + h) - force(p, dl, theta - h)) / (2 * h);
      const Eigen::Vector2d d_pressure =
          (force(p + h, dl, theta) - force(p - h, dl, theta)) / (2 * h);
      EXPECT_LT((f.d_force_d_delta_length - d_length).norm(), 1e-6)
          << VariantName(model);
      EXPECT_LT((f.d_force_d_theta - d_theta).norm(), 1e-6)
          << VariantName(model);
      EXPECT_LT((f.d_force_d_pressure - d_pressure).norm(), 1e-6)
          << VariantName(model);
    }
  }
}

TEST(ForceModel, PressurizedSpringDropsTheShearTerms) {
  const ForceModel spring = ForceModel::PressurizedSpring({});
  EXPECT_EQ(spring.constants.torsional_factor_n_per_rad, 0.0);
  EXPECT_EQ(spring.constants.shear_area_factor_mm2_per_rad, 0.0);
  EXPECT_EQ(spring.constants.axial_area_mm2, 157.0);
  EXPECT_EQ(spring.constants.linear_stiffness_n_per_mm, 2.71);
}

TEST(ForceModel, VariantNamesRoundTrip) {
  for (const char* name : {"small-angle", "full-trig", "variable-arm"}) {
    const std::optional<ForceModel> model = ForceModelFromVariantName(name, {});
    ASSERT_TRUE(model.has_value()) << name;
    EXPECT_EQ(VariantName(*model), name);
  }
  EXPECT_FALSE(ForceModelFromVariantName("small_angle", {}).has_value());
}

TEST(ActuatorConstants, ProblemNamesNonPhysicalValues) {
  EXPECT_FALSE(ActuatorConstants{}.Problem().has_value());
  ActuatorConstants c;
  c.linear_stiffness_n_per_mm = 0.0;
  EXPECT_TRUE(c.Problem().has_value());
  c = {};
  c.axial_area_mm2 = std::nan("");
  EXPECT_TRUE(c.Problem().has_value());
  c = {};
  c.natural_length_mm = -1.0;
  EXPECT_TRUE(c.Problem().has_value());
}

}  // namespace
}  // namespace softbench
