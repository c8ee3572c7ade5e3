#include "model/prediction.h"

#include <gtest/gtest.h>

#include "tests/model/thesis_mechanisms.h"

namespace softbench {
namespace {

// Warm starts change where a solve begins, never where it ends: every row's
// prediction equals a solve from rest, and each carries its range and reach.
TEST(PredictEquilibria, WarmStartsAgreeWithSolvesFromRestAndMarkTheRange) {
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::SmallAngle({}));
  const CharacterisedRange range;
  std::vector<Eigen::VectorXd> rows;
  for (double psi : {0.0, 2.0, 4.0, 6.0, 9.0, 3.0}) {
    rows.push_back(Eigen::Vector3d(psi, 0.5 * psi, 0.0) * kMpaPerPsi);
  }
  const std::vector<Prediction> predictions =
      PredictEquilibria(problem, range, rows);
  ASSERT_EQ(predictions.size(), rows.size());
  EquilibriumSolver cold(problem);
  for (size_t i = 0; i < rows.size(); ++i) {
    const Prediction& p = predictions[i];
    ASSERT_TRUE(p.summary.converged()) << i;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
    ASSERT_TRUE(cold.Solve(rows[i], &x).converged());
    EXPECT_LT((p.x - x).norm(), 1e-9) << "row " << i;
    // 9 psi is beyond the characterised 6 psi; the rest lie inside.
    EXPECT_EQ(p.outside_range.has_value(), i == 4) << "row " << i;
    EXPECT_TRUE(p.reach.within || i == 4) << "row " << i;
  }
  EXPECT_NE(predictions[4].outside_range->find("above the characterised"),
            std::string::npos)
      << *predictions[4].outside_range;
}

}  // namespace
}  // namespace softbench
