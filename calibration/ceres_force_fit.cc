#include "calibration/ceres_force_fit.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <memory>
#include <utility>

namespace softbench {
namespace {

// Residual L^T c - y of the bounded least-squares problem.
class NormalEquationsCost : public ceres::CostFunction {
 public:
  NormalEquationsCost(Eigen::MatrixXd lt, Eigen::VectorXd y)
      : lt_(std::move(lt)), y_(std::move(y)) {
    set_num_residuals(static_cast<int>(y_.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(y_.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int k = static_cast<int>(y_.size());
    const Eigen::Map<const Eigen::VectorXd> c(parameters[0], k);
    Eigen::Map<Eigen::VectorXd>(residuals, k) = lt_ * c - y_;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                               Eigen::RowMajor>>(jacobians[0], k, k) = lt_;
    }
    return true;
  }

 private:
  Eigen::MatrixXd lt_;
  Eigen::VectorXd y_;
};

// One logged row: weighted axial and shear residuals (Algorithm 1).
class RowCost : public ceres::CostFunction {
 public:
  RowCost(const FreeDesign* design, const ForceRow* row,
          Eigen::Vector2d weights)
      : design_(design), row_(row), weights_(std::move(weights)) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(
        static_cast<int>(design->u.cols()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int k = static_cast<int>(design_->u.cols());
    const Eigen::Map<const Eigen::VectorXd> c(parameters[0], k);
    const double p = row_->pressure_mpa;
    const Eigen::Matrix<double, 2, Eigen::Dynamic> a =
        p * design_->u + design_->v;
    const Eigen::Vector2d offset = p * design_->fixed_u + design_->fixed_v;
    const Eigen::Vector2d measured(row_->axial_n, row_->shear_n);
    const Eigen::Vector2d r = weights_.cwiseProduct(measured - a * c - offset);
    residuals[0] = r[0];
    residuals[1] = r[1];
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>>(
          jacobians[0], 2, k) = -(weights_.asDiagonal() * a);
    }
    return true;
  }

 private:
  const FreeDesign* design_;
  const ForceRow* row_;
  Eigen::Vector2d weights_;
};

CeresFitResult Solve(ceres::Problem* problem, double* values,
                     const Eigen::VectorXd& lower, int num_rows) {
  for (int i = 0; i < lower.size(); ++i) {
    if (std::isfinite(lower[i])) {
      problem->SetParameterLowerBound(values, i, lower[i]);
    }
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.num_threads = num_rows > 10000 ? 2 : 1;
  // Tight enough that a linear problem ends at its exact minimum (the
  // closed form cross-check agrees to 1e-9 relative).
  options.function_tolerance = 1e-20;
  options.gradient_tolerance = 1e-20;
  options.parameter_tolerance = 1e-16;
  // Near the minimum the cost's change falls below its rounding, and LM
  // would stop short of it: a wide first trust region makes the first step
  // the Gauss-Newton step, exact for a linear problem.
  options.initial_trust_region_radius = 1e12;
  options.max_num_iterations = 200;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem, &summary);
  CeresFitResult result;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  if (!result.converged) {
    result.why_not = "Ceres did not converge: " + summary.message;
  }
  return result;
}

}  // namespace

CeresFitResult SolveBoundedNormalEquations(const Eigen::MatrixXd& normal,
                                           const Eigen::VectorXd& rhs,
                                           const Eigen::VectorXd& lower,
                                           const Eigen::VectorXd& start) {
  const Eigen::LLT<Eigen::MatrixXd> llt(normal);
  const Eigen::MatrixXd l = llt.matrixL();
  const Eigen::VectorXd y = llt.matrixL().solve(rhs);
  Eigen::VectorXd values = start.cwiseMax(lower);
  ceres::Problem problem;
  problem.AddResidualBlock(new NormalEquationsCost(l.transpose(), y), nullptr,
                           values.data());
  CeresFitResult result = Solve(&problem, values.data(), lower, 1);
  result.values = values;
  return result;
}

CeresFitResult SolveRows(const std::vector<FreeDesign>& designs,
                         const std::vector<ForceRow>& rows,
                         const ForceFitOptions& options,
                         const Eigen::VectorXd& lower,
                         const Eigen::VectorXd& start) {
  std::unique_ptr<ceres::LossFunction> loss;
  if (options.loss == FitLoss::kHuber) {
    loss = std::make_unique<ceres::HuberLoss>(options.loss_scale_n);
  } else if (options.loss == FitLoss::kCauchy) {
    loss = std::make_unique<ceres::CauchyLoss>(options.loss_scale_n);
  }
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  // Rows are only added, never removed: skip Ceres's removal bookkeeping.
  problem_options.enable_fast_removal = false;
  ceres::Problem problem(problem_options);
  Eigen::VectorXd values = start.cwiseMax(lower);
  const Eigen::Vector2d weights(options.axial_weight, options.shear_weight);
  for (const ForceRow& row : rows) {
    problem.AddResidualBlock(new RowCost(&designs[row.test], &row, weights),
                             loss.get(), values.data());
  }
  CeresFitResult result =
      Solve(&problem, values.data(), lower, static_cast<int>(rows.size()));
  result.values = values;
  return result;
}

}  // namespace softbench
