#include "model/mechanism.h"

#include <gtest/gtest.h>

#include "model/units.h"
#include "tests/model/thesis_mechanisms.h"

namespace softbench {
namespace {

TEST(Mechanism, ThesisMechanismsAreWellFormed) {
  EXPECT_FALSE(testing::DeltaMechanism().Problem().has_value());
  EXPECT_FALSE(testing::FloatingMechanism().Problem().has_value());
  EXPECT_FALSE(testing::ThreeHeadChain().Problem().has_value());
}

TEST(Mechanism, RestLengthsAreTheSpecsDistances) {
  const Mechanism delta = testing::DeltaMechanism();
  for (const Actuator& a : delta.actuators) {
    EXPECT_NEAR(delta.RestLength(a), 27.0, 1e-12);
  }
  const Mechanism floating = testing::FloatingMechanism();
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(floating.RestLength(floating.actuators[i]), 31.15, 0.01);
  }
  EXPECT_NEAR(floating.RestLength(floating.actuators[4]), 39.70, 1e-12);
}

TEST(Mechanism, RotationXIsTheThesisMatrices) {
  // Eq. 4.2: 0R2 restricted to (y, z) = [[-0.5, -0.866], [0.866, -0.5]].
  const Eigen::Matrix2d r2 = RotationX(DegToRad(120.0));
  EXPECT_NEAR(r2(0, 0), -0.5, 1e-12);
  EXPECT_NEAR(r2(0, 1), -0.8660254, 1e-7);
  EXPECT_NEAR(r2(1, 0), 0.8660254, 1e-7);
  EXPECT_NEAR(r2(1, 1), -0.5, 1e-12);
}

TEST(Mechanism, RestAxisRotationFollowsTheGeometry) {
  const Mechanism floating = testing::FloatingMechanism();
  for (const Actuator& a : floating.actuators) {
    EXPECT_NEAR(floating.RestAxisRotation(a), a.rotation_rad, 1e-4) << a.name;
  }
}

TEST(Mechanism, ProblemNamesARotationThatContradictsTheGeometry) {
  Mechanism m = testing::DeltaMechanism();
  m.actuators[1].rotation_rad = DegToRad(-120.0);
  const std::optional<MechanismProblem> problem = m.Problem();
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(problem->actuator, 1);
  EXPECT_NE(problem->message.find("actuator '2'"), std::string::npos)
      << problem->message;
  EXPECT_NE(problem->message.find("set rotation_deg to 120 "),
            std::string::npos)
      << problem->message;
}

TEST(Mechanism, ProblemNamesAHeadNotTiedToTheGround) {
  Mechanism m = testing::FloatingMechanism();
  m.actuators.erase(m.actuators.begin() + 2, m.actuators.begin() + 4);
  m.actuators.pop_back();  // the right head is now free
  const std::optional<MechanismProblem> problem = m.Problem();
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(problem->head, 1);
  EXPECT_NE(problem->message.find("'right'"), std::string::npos)
      << problem->message;
}

TEST(Mechanism, ProblemNamesAnActuatorFromAHeadToItself) {
  Mechanism m = testing::FloatingMechanism();
  m.actuators[4].anchor = {AnchorRef::Kind::kHead, 1};
  EXPECT_TRUE(m.Problem().has_value());
}

TEST(Mechanism, ProblemNamesBadIndices) {
  Mechanism m = testing::DeltaMechanism();
  m.actuators[0].anchor.index = 7;
  EXPECT_TRUE(m.Problem().has_value());
  m = testing::DeltaMechanism();
  m.actuators[0].head = 1;
  EXPECT_TRUE(m.Problem().has_value());
}

}  // namespace
}  // namespace softbench
