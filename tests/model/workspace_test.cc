#include "model/workspace.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "model/units.h"
#include "tests/model/thesis_mechanisms.h"

namespace softbench {
namespace {

WorkspaceOptions PsiLevels(double max_psi, double step_psi, int threads = 0) {
  WorkspaceOptions options;
  options.pressure_levels_mpa = EvenPressureLevels(
      max_psi * kMpaPerPsi, static_cast<int>(std::lround(max_psi / step_psi)));
  options.num_threads = threads;
  return options;
}

TEST(Workspace, DeltaExtentsMatchTheThesis) {
  // model.md: y about +-1.12 mm, z -1.30 .. +1.29 mm over 343 points.
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::SmallAngle({}));
  const WorkspaceMap map = ComputeWorkspace(problem, PsiLevels(6, 1));
  ASSERT_EQ(map.pressures_mpa.rows(), 343);
  EXPECT_EQ(map.num_not_converged, 0);
  const HeadExtents e = map.Extents()[0];
  EXPECT_NEAR(e.min_mm.x(), -1.12, 0.01);
  EXPECT_NEAR(e.max_mm.x(), 1.12, 0.01);
  EXPECT_NEAR(e.min_mm.y(), -1.30, 0.01);
  EXPECT_NEAR(e.max_mm.y(), 1.29, 0.01);
}

TEST(Workspace, FloatingExtentsMatchTheThesis) {
  // model.md: left z -1.94 .. +1.89, right z -1.89 .. +1.94, y +-1.30 mm;
  // the floating actuator's dL5 spans more than 3 mm, theta5 about 6 deg.
  const EquilibriumProblem problem(testing::FloatingMechanism(),
                                   ForceModel::SmallAngle({}));
  const WorkspaceMap map = ComputeWorkspace(problem, PsiLevels(6, 1.5));
  ASSERT_EQ(map.pressures_mpa.rows(), 3125);
  EXPECT_EQ(map.num_not_converged, 0);
  const std::vector<HeadExtents> e = map.Extents();
  EXPECT_NEAR(e[0].min_mm.y(), -1.94, 0.01);
  EXPECT_NEAR(e[0].max_mm.y(), 1.89, 0.01);
  EXPECT_NEAR(e[1].min_mm.y(), -1.89, 0.01);
  EXPECT_NEAR(e[1].max_mm.y(), 1.94, 0.01);
  for (int h = 0; h < 2; ++h) {
    EXPECT_NEAR(e[h].min_mm.x(), -1.30, 0.01);
    EXPECT_NEAR(e[h].max_mm.x(), 1.30, 0.01);
  }
  double dl_min = 0, dl_max = 0, theta_min = 0, theta_max = 0;
  for (int i = 0; i < map.displacements_mm.rows(); ++i) {
    const Deformation d =
        problem.Deformations(map.displacements_mm.row(i).transpose())[4];
    dl_min = std::min(dl_min, d.delta_length_mm);
    dl_max = std::max(dl_max, d.delta_length_mm);
    theta_min = std::min(theta_min, d.theta_rad);
    theta_max = std::max(theta_max, d.theta_rad);
  }
  EXPECT_GT(dl_max - dl_min, 3.0);
  EXPECT_NEAR(RadToDeg(theta_max - theta_min), 6.0, 1.0);
}

TEST(Workspace, RowsAreLexicographicAndEqualColdSolves) {
  const EquilibriumProblem problem(testing::FloatingMechanism(),
                                   ForceModel::FullTrigonometric({}));
  const WorkspaceOptions options = PsiLevels(6, 3);
  const WorkspaceMap map = ComputeWorkspace(problem, options);
  ASSERT_EQ(map.pressures_mpa.rows(), 243);
  EquilibriumSolver solver(problem);
  for (int i = 0; i < map.pressures_mpa.rows(); ++i) {
    // Row i's level of actuator k is digit k of i in base 3, p1 slowest.
    int rest = i;
    for (int k = 4; k >= 0; --k) {
      EXPECT_DOUBLE_EQ(map.pressures_mpa(i, k),
                       options.pressure_levels_mpa[rest % 3]);
      rest /= 3;
    }
    Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
    ASSERT_TRUE(
        solver.Solve(map.pressures_mpa.row(i).transpose(), &x).converged());
    EXPECT_LT((map.displacements_mm.row(i).transpose() - x).norm(), 1e-9);
  }
}

TEST(Workspace, ThreadCountDoesNotChangeTheMap) {
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::VariableMomentArm({}));
  const WorkspaceMap one = ComputeWorkspace(problem, PsiLevels(6, 0.5, 1));
  const WorkspaceMap four = ComputeWorkspace(problem, PsiLevels(6, 0.5, 4));
  // Runs of the sweep are fixed, whichever thread takes them: the maps agree
  // to the last bit.
  EXPECT_EQ(one.pressures_mpa, four.pressures_mpa);
  EXPECT_EQ(one.displacements_mm, four.displacements_mm);
}

// Up to 8 psi against a range characterised to 6 psi: the rows the workers
// mark are exactly those OutsideCharacterisedRange names, one by one.
TEST(Workspace, MarksTheRowsBeyondTheCharacterisedRange) {
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::SmallAngle({}));
  WorkspaceOptions options = PsiLevels(8, 1, 2);
  options.range = CharacterisedRange();
  const WorkspaceMap map = ComputeWorkspace(problem, options);
  ASSERT_EQ(map.in_range.size(), 729u);
  int outside = 0;
  for (Eigen::Index i = 0; i < map.pressures_mpa.rows(); ++i) {
    const bool beyond =
        OutsideCharacterisedRange(*options.range, problem,
                                  map.pressures_mpa.row(i).transpose(),
                                  map.displacements_mm.row(i).transpose())
            .has_value();
    EXPECT_EQ(map.in_range[i] == 0, beyond) << "row " << i;
    outside += beyond ? 1 : 0;
  }
  // Every row with a 7 or 8 psi level (729 - 7^3), and none without a range.
  EXPECT_EQ(map.num_outside_range, outside);
  EXPECT_GE(outside, 729 - 343);
  options.range.reset();
  EXPECT_EQ(ComputeWorkspace(problem, options).num_outside_range, 0);
}

TEST(WorkspaceOptions, ProblemNamesBadLevels) {
  WorkspaceOptions options;
  EXPECT_TRUE(options.Problem().has_value());
  options.pressure_levels_mpa = {0.0, -0.01};
  EXPECT_TRUE(options.Problem().has_value());
  options.pressure_levels_mpa = {0.0, 0.01};
  EXPECT_FALSE(options.Problem().has_value());
}

}  // namespace
}  // namespace softbench
