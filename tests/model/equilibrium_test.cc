#include "model/equilibrium.h"

#include <gtest/gtest.h>

#include <random>

#include "model/units.h"
#include "tests/model/thesis_mechanisms.h"

namespace softbench {
namespace {

struct TablePoint {
  double p1, p2, p3;  // psi
  double y, z;        // mm, as printed in Table 4.1
};

// Thesis Table 4.1 (model.md).
const TablePoint kTable41[] = {{6, 6, 0, -1.12, 0.65}, {6, 3, 0, -0.56, 0.97},
                               {6, 0, 0, 0.00, 1.29},  {4, 6, 1, -0.94, 0.11},
                               {5, 5, 2, -0.56, 0.33}, {4, 2, 1, -0.19, 0.54},
                               {5, 5, 4, -0.19, 0.11}};

Eigen::VectorXd Psi(std::initializer_list<double> psi) {
  Eigen::VectorXd p(psi.size());
  int i = 0;
  for (double value : psi) p[i++] = value * kMpaPerPsi;
  return p;
}

Eigen::VectorXd SolveOrFail(const EquilibriumProblem& problem,
                            const Eigen::VectorXd& pressures_mpa) {
  EquilibriumSolver solver(problem);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
  const EquilibriumSummary summary = solver.Solve(pressures_mpa, &x);
  EXPECT_TRUE(summary.converged()) << summary.Message();
  return x;
}

TEST(Equilibrium, ReproducesThesisTable41) {
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::SmallAngle({}));
  for (const TablePoint& point : kTable41) {
    const Eigen::VectorXd x =
        SolveOrFail(problem, Psi({point.p1, point.p2, point.p3}));
    EXPECT_NEAR(x[0], point.y, 0.01)
        << point.p1 << "," << point.p2 << "," << point.p3;
    EXPECT_NEAR(x[1], point.z, 0.01)
        << point.p1 << "," << point.p2 << "," << point.p3;
  }
}

TEST(Equilibrium, BaselineOverPredictsEveryTable41Point) {
  // Thesis 4.1.3: the pressurized spring "significantly over predicts the
  // total magnitude of deflection".
  const EquilibriumProblem model(testing::DeltaMechanism(),
                                 ForceModel::SmallAngle({}));
  const EquilibriumProblem baseline(testing::DeltaMechanism(),
                                    ForceModel::PressurizedSpring({}));
  for (const TablePoint& point : kTable41) {
    const Eigen::VectorXd p = Psi({point.p1, point.p2, point.p3});
    EXPECT_GT(SolveOrFail(baseline, p).norm(), SolveOrFail(model, p).norm())
        << point.p1 << "," << point.p2 << "," << point.p3;
  }
}

TEST(Equilibrium, RestIsTheZeroSolution) {
  for (const Mechanism& m :
       {testing::DeltaMechanism(), testing::FloatingMechanism(),
        testing::ThreeHeadChain()}) {
    const EquilibriumProblem problem(m, ForceModel::SmallAngle({}));
    Eigen::VectorXd residual;
    ASSERT_TRUE(problem.Evaluate(Eigen::VectorXd::Zero(problem.NumActuators()),
                                 Eigen::VectorXd::Zero(problem.NumUnknowns()),
                                 &residual));
    EXPECT_LT(residual.lpNorm<Eigen::Infinity>(), 1e-12) << m.name;
  }
}

TEST(Equilibrium, DeltaIsMirrorSymmetric) {
  // Swapping p2 and p3 mirrors the head about the z axis (fig. 4.6).
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::FullTrigonometric({}));
  const Eigen::VectorXd a = SolveOrFail(problem, Psi({4, 6, 1}));
  const Eigen::VectorXd b = SolveOrFail(problem, Psi({4, 1, 6}));
  EXPECT_NEAR(a[0], -b[0], 1e-10);
  EXPECT_NEAR(a[1], b[1], 1e-10);
}

TEST(Equilibrium, FloatingIsPointSymmetricUnderSwappedHeads) {
  // Rotating the floating mechanism by 180 deg about the middle of its rest
  // heads maps actuators 1<->3, 2<->4, keeps 5, and swaps the heads.
  const EquilibriumProblem problem(testing::FloatingMechanism(),
                                   ForceModel::SmallAngle({}));
  const Eigen::VectorXd a = SolveOrFail(problem, Psi({6, 1.5, 3, 0, 4.5}));
  const Eigen::VectorXd b = SolveOrFail(problem, Psi({3, 0, 6, 1.5, 4.5}));
  EXPECT_NEAR((a.head<2>() + b.tail<2>()).norm(), 0.0, 1e-9);
  EXPECT_NEAR((a.tail<2>() + b.head<2>()).norm(), 0.0, 1e-9);
}

TEST(EquilibriumProblem, JacobiansMatchCentralDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> displacement(-2.0, 2.0);
  std::uniform_real_distribution<double> pressure(0.0, 0.045);
  const double h = 1e-6;
  for (const Mechanism& m :
       {testing::DeltaMechanism(), testing::FloatingMechanism(),
        testing::ThreeHeadChain()}) {
    for (const ForceModel& model :
         {ForceModel::SmallAngle({}), ForceModel::FullTrigonometric({}),
          ForceModel::VariableMomentArm({})}) {
      const EquilibriumProblem problem(m, model);
      for (int trial = 0; trial < 20; ++trial) {
        Eigen::VectorXd x(problem.NumUnknowns()), p(problem.NumActuators());
        for (double& v : x) v = displacement(rng);
        for (double& v : p) v = pressure(rng);
        Eigen::VectorXd r, r_plus, r_minus;
        Eigen::MatrixXd jx, jp;
        ASSERT_TRUE(problem.Evaluate(p, x, &r, &jx, &jp));
        for (int i = 0; i < x.size(); ++i) {
          Eigen::VectorXd xp = x, xm = x;
          xp[i] += h;
          xm[i] -= h;
          problem.Evaluate(p, xp, &r_plus);
          problem.Evaluate(p, xm, &r_minus);
          EXPECT_LT((jx.col(i) - (r_plus - r_minus) / (2 * h)).norm(), 1e-6)
              << m.name << " " << VariantName(model) << " x" << i;
        }
        for (int k = 0; k < p.size(); ++k) {
          Eigen::VectorXd pp = p, pm = p;
          pp[k] += h;
          pm[k] -= h;
          problem.Evaluate(pp, x, &r_plus);
          problem.Evaluate(pm, x, &r_minus);
          EXPECT_LT((jp.col(k) - (r_plus - r_minus) / (2 * h)).norm(), 1e-6)
              << m.name << " " << VariantName(model) << " p" << k;
        }
      }
    }
  }
}

TEST(Equilibrium, UserWrittenThreeHeadChainSolvesTightly) {
  const EquilibriumProblem problem(testing::ThreeHeadChain(),
                                   ForceModel::SmallAngle({}));
  const Eigen::VectorXd p = Psi({6, 2, 4, 1, 5, 3, 6});
  EquilibriumSolver solver(problem);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
  const EquilibriumSummary summary = solver.Solve(p, &x);
  ASSERT_TRUE(summary.converged()) << summary.Message();
  Eigen::VectorXd residual;
  ASSERT_TRUE(problem.Evaluate(p, x, &residual));
  EXPECT_LT(residual.lpNorm<Eigen::Infinity>(), 1e-9);
  // Every head moved: the network is genuinely coupled.
  for (int h = 0; h < 3; ++h) EXPECT_GT(x.segment<2>(2 * h).norm(), 0.05);
}

TEST(EquilibriumSolver, ReportsAnIterationLimitAsNotConverged) {
  const EquilibriumProblem problem(testing::FloatingMechanism(),
                                   ForceModel::SmallAngle({}));
  EquilibriumOptions options;
  options.max_iterations = 1;
  EquilibriumSolver solver(problem, options);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
  const EquilibriumSummary summary = solver.Solve(Psi({6, 0, 6, 0, 6}), &x);
  EXPECT_FALSE(summary.converged());
  EXPECT_EQ(summary.termination, EquilibriumTermination::kMaxIterations);
  EXPECT_GT(summary.max_residual_n, options.function_tolerance_n);
  EXPECT_NE(summary.Message().find("not converged"), std::string::npos);
}

TEST(EquilibriumSolver, ReportsAnUndefinedStartingPoint) {
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::SmallAngle({}));
  EquilibriumSolver solver(problem);
  // The head sits on anchor 1, where theta is undefined.
  Eigen::VectorXd x(2);
  x << 0.0, -27.0;
  const EquilibriumSummary summary = solver.Solve(Psi({1, 1, 1}), &x);
  EXPECT_EQ(summary.termination, EquilibriumTermination::kInvalidStartingPoint);
}

TEST(EquilibriumSolver, RecoversFromAFarStartingPoint) {
  // Far from the solution the Newton step overshoots; the line search and
  // damped fallback must still bring it home.
  const EquilibriumProblem problem(testing::FloatingMechanism(),
                                   ForceModel::FullTrigonometric({}));
  EquilibriumSolver solver(problem);
  const Eigen::VectorXd p = Psi({6, 0, 0, 6, 3});
  Eigen::VectorXd far(4);
  far << 9.0, -7.0, -8.0, 6.0;
  const EquilibriumSummary summary = solver.Solve(p, &far);
  ASSERT_TRUE(summary.converged()) << summary.Message();
  EXPECT_LT((far - SolveOrFail(problem, p)).norm(), 1e-8);
}

// The prediction's error at the solution a step h away along actuator 1 of
// the floating mechanism, from (3, 2, 4, 1, 2) psi. With `learn`, the solver
// first steps to the base from h behind, which teaches it the path's
// curvature along that actuator.
double PredictionError(double h_psi, bool learn) {
  const EquilibriumProblem problem(testing::FloatingMechanism(),
                                   ForceModel::VariableMomentArm({}));
  EquilibriumSolver solver(problem);
  const Eigen::VectorXd base = Psi({3, 2, 4, 1, 2});
  Eigen::VectorXd step = Eigen::VectorXd::Zero(5);
  step[1] = h_psi * kMpaPerPsi;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  if (learn) {
    EXPECT_TRUE(solver.Solve(base - step, &x).converged());
  }
  solver.PredictSolution(base, &x);
  EXPECT_TRUE(solver.Solve(base, &x).converged());
  Eigen::VectorXd predicted = x;
  solver.PredictSolution(base + step, &predicted);
  return (predicted - SolveOrFail(problem, base + step)).norm();
}

TEST(EquilibriumSolver, PredictionIsSecondOrderAlongTheTangent) {
  // Halving the step quarters a first-order prediction's error.
  const double ratio =
      PredictionError(0.8, false) / PredictionError(0.4, false);
  EXPECT_GT(ratio, 3.5);
  EXPECT_LT(ratio, 4.5);
}

TEST(EquilibriumSolver, LearnedCurvatureMakesThePredictionThirdOrder) {
  // With the curvature of the step before, halving the step divides the
  // error by eight, and it is far below the tangent's alone.
  const double ratio = PredictionError(0.8, true) / PredictionError(0.4, true);
  EXPECT_GT(ratio, 7.0);
  EXPECT_LT(ratio, 9.0);
  EXPECT_LT(PredictionError(0.8, true), 0.05 * PredictionError(0.8, false));
}

TEST(EquilibriumSolver, PredictionDoesNothingWithoutAConvergedSolve) {
  const EquilibriumProblem problem(testing::DeltaMechanism(),
                                   ForceModel::SmallAngle({}));
  EquilibriumSolver solver(problem);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(2, 0.25);
  solver.PredictSolution(Psi({1, 2, 3}), &x);
  EXPECT_EQ(x, Eigen::VectorXd::Constant(2, 0.25));
}

}  // namespace
}  // namespace softbench
