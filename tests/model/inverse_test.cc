#include "model/inverse.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/model/thesis_mechanisms.h"

namespace softbench {
namespace {

Eigen::VectorXd Forward(const EquilibriumProblem& problem,
                        const Eigen::VectorXd& pressures_mpa) {
  EquilibriumSolver solver(problem);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
  EXPECT_TRUE(solver.Solve(pressures_mpa, &x).converged());
  return x;
}

TEST(Inverse, RecoversPressuresThatReproducePredictedPoints) {
  std::mt19937 rng(3);
  const InverseOptions options;
  std::uniform_real_distribution<double> pressure(0.0,
                                                  options.max_pressure_mpa);
  for (const Mechanism& m :
       {testing::DeltaMechanism(), testing::FloatingMechanism()}) {
    const EquilibriumProblem problem(m, ForceModel::SmallAngle({}));
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd p(problem.NumActuators());
      for (double& v : p) v = pressure(rng);
      const Eigen::VectorXd target = Forward(problem, p);
      const InverseResult result = SolvePressuresForTarget(problem, target);
      ASSERT_TRUE(result.reachable) << m.name << " " << result.message;
      EXPECT_LT((Forward(problem, result.pressures_mpa) - target).norm(), 1e-6);
      EXPECT_GE(result.pressures_mpa.minCoeff(), 0.0);
      EXPECT_LE(result.pressures_mpa.maxCoeff(), options.max_pressure_mpa);
    }
  }
}

TEST(Inverse, ChoosesTheMinimumPressureSolution) {
  // Raising all three delta pressures together barely moves the head, so a
  // point reached with (5, 5, 2) psi is also reached with less pressure; the
  // least-norm answer vents one actuator completely.
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::SmallAngle({}));
  const Eigen::VectorXd given = Eigen::Vector3d(5, 5, 2) * kMpaPerPsi;
  const Eigen::VectorXd target = Forward(problem, given);
  const InverseResult result = SolvePressuresForTarget(problem, target);
  ASSERT_TRUE(result.reachable) << result.message;
  EXPECT_LT(result.pressures_mpa.norm(), given.norm());
  EXPECT_LT(result.pressures_mpa.minCoeff(), 1e-6);
  EXPECT_LT((Forward(problem, result.pressures_mpa) - target).norm(), 1e-6);
  // No feasible neighbour along the equal-pressure direction is smaller.
  const Eigen::VectorXd lower =
      result.pressures_mpa - Eigen::VectorXd::Constant(3, 0.01 * kMpaPerPsi);
  EXPECT_LT(lower.minCoeff(), 0.0);
}

TEST(Inverse, SaysUnreachableAndGivesTheClosestReachablePoint) {
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::SmallAngle({}));
  const Eigen::VectorXd target = Eigen::Vector2d(0.0, 3.0);  // beyond 1.29
  const InverseResult result = SolvePressuresForTarget(problem, target);
  ASSERT_TRUE(result.solved);
  EXPECT_FALSE(result.reachable);
  // Straight up, the farthest point is actuator 1 alone at full pressure.
  EXPECT_NEAR(result.displacements_mm[0], 0.0, 1e-4);
  EXPECT_NEAR(result.displacements_mm[1],
              Forward(problem, Eigen::Vector3d(6, 0, 0) * kMpaPerPsi)[1], 1e-4);
  EXPECT_NEAR(result.distance_mm, (result.displacements_mm - target).norm(),
              1e-12);
  EXPECT_LT(
      (Forward(problem, result.pressures_mpa) - result.displacements_mm).norm(),
      1e-9);
}

}  // namespace
}  // namespace softbench
