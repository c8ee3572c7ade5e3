#include "model/inverse.h"

#include <ceres/ceres.h>

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "util/check.h"

namespace softbench {
namespace {

// Residuals: the heads' position error [mm], then sqrt(w) * P / P_max. The
// parameters are the normalised pressures u = P / P_max in [0, 1].
class TargetCost : public ceres::CostFunction {
 public:
  TargetCost(const EquilibriumProblem& problem, Eigen::VectorXd target,
             const InverseOptions& options)
      : problem_(problem),
        target_(std::move(target)),
        options_(options),
        solver_(problem, options.equilibrium),
        warm_start_(Eigen::VectorXd::Zero(problem.NumUnknowns())) {
    set_num_residuals(problem.NumUnknowns() + problem.NumActuators());
    mutable_parameter_block_sizes()->push_back(problem.NumActuators());
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int n = problem_.NumUnknowns();
    const int m = problem_.NumActuators();
    const Eigen::Map<const Eigen::VectorXd> u(parameters[0], m);
    const Eigen::VectorXd pressures = u * options_.max_pressure_mpa;
    Eigen::VectorXd x = warm_start_;
    if (!solver_.Solve(pressures, &x).converged()) {
      x.setZero();
      if (!solver_.Solve(pressures, &x).converged()) return false;
    }
    warm_start_ = x;
    const double root_weight = std::sqrt(options_.pressure_weight);
    Eigen::Map<Eigen::VectorXd> r(residuals, n + m);
    r.head(n) = x - target_;
    r.tail(m) = root_weight * u;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::VectorXd force;
      Eigen::MatrixXd d_force_d_x, d_force_d_p;
      problem_.Evaluate(pressures, x, &force, &d_force_d_x, &d_force_d_p);
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                               Eigen::RowMajor>>
          jacobian(jacobians[0], n + m, m);
      jacobian.topRows(n) = -d_force_d_x.partialPivLu().solve(d_force_d_p) *
                            options_.max_pressure_mpa;
      jacobian.bottomRows(m) = root_weight * Eigen::MatrixXd::Identity(m, m);
      if (!jacobian.allFinite()) return false;
    }
    return true;
  }

 private:
  const EquilibriumProblem& problem_;
  Eigen::VectorXd target_;
  InverseOptions options_;
  mutable EquilibriumSolver solver_;
  mutable Eigen::VectorXd warm_start_;
};

}  // namespace

std::optional<std::string> InverseOptions::Problem() const {
  if (!(max_pressure_mpa > 0.0) || !std::isfinite(max_pressure_mpa)) {
    return "max_pressure_mpa must be a finite number > 0";
  }
  if (!(reach_tolerance_mm > 0.0)) return "reach_tolerance_mm must be > 0";
  if (!(pressure_weight >= 0.0)) return "pressure_weight must be >= 0";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  return equilibrium.Problem();
}

InverseResult SolvePressuresForTarget(const EquilibriumProblem& problem,
                                      const Eigen::VectorXd& target_mm,
                                      const InverseOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  SOFTBENCH_CHECK(target_mm.size() == problem.NumUnknowns())
      << "target of " << target_mm.size() << " values for "
      << problem.NumUnknowns() << " unknowns";
  const int m = problem.NumActuators();

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  // A large trust region makes the steps Gauss-Newton steps, which move
  // along the near-null directions that only the small pressure weight sees.
  solver_options.initial_trust_region_radius = 1e12;
  solver_options.function_tolerance = 1e-18;
  solver_options.gradient_tolerance = 1e-20;
  solver_options.parameter_tolerance = 1e-14;
  solver_options.logging_type = ceres::SILENT;

  // Starts: mid-range pressures, then each actuator alone at mid-range.
  std::vector<Eigen::VectorXd> starts = {Eigen::VectorXd::Constant(m, 0.5)};
  for (int k = 0; k < m; ++k) {
    starts.emplace_back(Eigen::VectorXd::Constant(m, 0.05));
    starts.back()[k] = 0.5;
  }

  InverseResult best;
  best.distance_mm = std::numeric_limits<double>::infinity();
  best.message = "no start converged to an equilibrium";
  for (const Eigen::VectorXd& start : starts) {
    Eigen::VectorXd u = start;
    ceres::Problem ceres_problem;
    ceres_problem.AddResidualBlock(new TargetCost(problem, target_mm, options),
                                   nullptr, u.data());
    for (int k = 0; k < m; ++k) {
      ceres_problem.SetParameterLowerBound(u.data(), k, 0.0);
      ceres_problem.SetParameterUpperBound(u.data(), k, 1.0);
    }
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &ceres_problem, &summary);
    if (!summary.IsSolutionUsable()) continue;

    // Re-solve the equilibrium at the found pressures from rest, so the
    // reported position does not depend on the optimiser's warm starts.
    const Eigen::VectorXd pressures = u * options.max_pressure_mpa;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
    EquilibriumSolver solver(problem, options.equilibrium);
    if (!solver.Solve(pressures, &x).converged()) continue;
    const double distance = (x - target_mm).norm();
    if (distance < best.distance_mm) {
      best.solved = true;
      best.pressures_mpa = pressures;
      best.displacements_mm = x;
      best.distance_mm = distance;
      best.reachable = distance <= options.reach_tolerance_mm;
      best.message = summary.BriefReport();
    }
    if (best.reachable) break;
  }
  return best;
}

ReachCheck CheckWithinReach(const EquilibriumProblem& problem,
                            const Eigen::VectorXd& x_mm,
                            double max_pressure_mpa, double tolerance_mm) {
  SOFTBENCH_CHECK(tolerance_mm > 0.0) << tolerance_mm;
  InverseOptions options;
  options.max_pressure_mpa = max_pressure_mpa;
  options.reach_tolerance_mm = tolerance_mm;
  const InverseResult closest = SolvePressuresForTarget(problem, x_mm, options);
  if (!closest.solved) {
    return {false, std::numeric_limits<double>::quiet_NaN()};
  }
  return {closest.reachable, closest.reachable ? 0.0 : closest.distance_mm};
}

ReachCheck ReachOfPrediction(const EquilibriumProblem& problem,
                             const CharacterisedRange& range,
                             const Eigen::VectorXd& pressures_mpa,
                             const Eigen::VectorXd& x_mm) {
  if (!PressuresOutsideCharacterisedRange(range, pressures_mpa)) return {};
  return CheckWithinReach(problem, x_mm, range.max_pressure_mpa);
}

}  // namespace softbench
