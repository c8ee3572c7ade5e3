#include "calibration/force_fit.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "calibration/ceres_force_fit.h"
#include "util/check.h"

namespace softbench {
namespace {

// Why a constant may be impossible to fit from a set of tests.
constexpr std::array<const char*, kNumFitConstants> kIdentifiabilityHint = {
    "no rows above zero pressure",
    "too few pressurized rows at theta != 0 (add tests at an angle)",
    "too few tests at dL != 0 (add extended or compressed tests)",
    "too few tests at theta != 0 (add tests at an angle)"};

struct NormalEquations {
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
  // Unweighted normal matrix of each direction, for standard errors.
  std::array<Eigen::Matrix4d, 2> direction_normal = {Eigen::Matrix4d::Zero(),
                                                     Eigen::Matrix4d::Zero()};
};

// Accumulates the normal equations from each test's centred moments:
// sum over rows of a a^T with a = P u + v is C_PP u u^T + n m m^T, m = P̄ u +
// v (and likewise for a F), so no raw sums of squares are ever subtracted.
NormalEquations AccumulateNormalEquations(const ForceModel& model,
                                          const std::vector<ForceTest>& tests,
                                          const ForceFitOptions& options) {
  NormalEquations equations;
  const std::array<double, 2> weights = {options.axial_weight,
                                         options.shear_weight};
  for (const ForceTest& test : tests) {
    const TestDesign design =
        DesignOfTest(model, test.delta_length_mm(), test.theta_rad());
    const ForceMoments m = test.statistics.All();
    if (m.count == 0) continue;
    const double n = static_cast<double>(m.count);
    for (int d = 0; d < 2; ++d) {
      const Eigen::Vector4d u = design.u.row(d).transpose();
      const Eigen::Vector4d mean_a =
          m.mean[0] * u + design.v.row(d).transpose();
      const Eigen::Matrix4d block = m.comoment(0, 0) * u * u.transpose() +
                                    n * mean_a * mean_a.transpose();
      const double w2 = weights[d] * weights[d];
      equations.direction_normal[d] += block;
      equations.normal += w2 * block;
      equations.rhs +=
          w2 * (m.comoment(0, 1 + d) * u + n * m.mean[1 + d] * mean_a);
    }
  }
  return equations;
}

std::vector<int> FreeIndices(const FitModel& fit_model) {
  std::vector<int> indices;
  for (int i = 0; i < kNumFitConstants; ++i) {
    if (fit_model.free[i]) indices.push_back(i);
  }
  return indices;
}

Eigen::MatrixXd Restrict(const Eigen::Matrix4d& matrix,
                         const std::vector<int>& indices) {
  const int k = static_cast<int>(indices.size());
  Eigen::MatrixXd out(k, k);
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) out(i, j) = matrix(indices[i], indices[j]);
  }
  return out;
}

// Lower bounds of the free constants: A_z, W_y, k_theta >= 0; k_s > 0 is
// kept as >= 0 (a fit that reaches 0 is reported at its bound).
Eigen::VectorXd LowerBounds(const std::vector<int>& free,
                            const ForceFitOptions& options) {
  return Eigen::VectorXd::Constant(static_cast<int>(free.size()),
                                   options.non_negative ? 0.0 : -INFINITY);
}

}  // namespace

Eigen::Vector4d ConstantsVector(const ActuatorConstants& constants) {
  return {constants.axial_area_mm2, constants.shear_area_factor_mm2_per_rad,
          constants.linear_stiffness_n_per_mm,
          constants.torsional_factor_n_per_rad};
}

ActuatorConstants ConstantsFromVector(const Eigen::Vector4d& values,
                                      const ActuatorConstants& base) {
  ActuatorConstants constants = base;
  constants.axial_area_mm2 = values[0];
  constants.shear_area_factor_mm2_per_rad = values[1];
  constants.linear_stiffness_n_per_mm = values[2];
  constants.torsional_factor_n_per_rad = values[3];
  return constants;
}

std::vector<FitModel> FitModel::ThesisModels(const ActuatorConstants& base) {
  FitModel spring{"pressurized-spring",
                  ForceModel::PressurizedSpring(base),
                  {true, false, true, false}};
  return {{"small-angle", ForceModel::SmallAngle(base)},
          {"full-trig", ForceModel::FullTrigonometric(base)},
          {"variable-arm", ForceModel::VariableMomentArm(base)},
          spring};
}

int FitModel::NumFree() const {
  int count = 0;
  for (bool is_free : free) count += is_free ? 1 : 0;
  return count;
}

std::optional<std::string> ForceFitOptions::Problem() const {
  if (!(axial_weight >= 0.0) || !(shear_weight >= 0.0) ||
      !std::isfinite(axial_weight) || !std::isfinite(shear_weight) ||
      axial_weight + shear_weight == 0.0) {
    return "axial and shear weights must be finite, >= 0 and not both 0";
  }
  if (!(loss_scale_n > 0.0) || !std::isfinite(loss_scale_n)) {
    return "loss scale must be a finite number > 0 N";
  }
  if (!(max_condition_number > 1.0)) return "max_condition_number must be > 1";
  if (!(max_relative_standard_error > 0.0)) {
    return "max_relative_standard_error must be > 0";
  }
  return std::nullopt;
}

TestDesign DesignOfTest(const ForceModel& model, double delta_length_mm,
                        double theta_rad) {
  // Every variant is linear in (A_z, W_y, k_s, k_theta): evaluating the model
  // with one constant at 1 and the others at 0 gives that constant's column.
  TestDesign design;
  const Deformation deformation{delta_length_mm, theta_rad};
  for (int i = 0; i < kNumFitConstants; ++i) {
    ForceModel unit = model;
    unit.constants =
        ConstantsFromVector(Eigen::Vector4d::Unit(i), model.constants);
    // force_in_local_n is (F_y, F_z): shear first.
    const Eigen::Vector2d at_zero =
        EvaluateActuatorForce(unit, 0.0, deformation).force_in_local_n;
    const Eigen::Vector2d at_one =
        EvaluateActuatorForce(unit, 1.0, deformation).force_in_local_n;
    design.v.col(i) << at_zero[1], at_zero[0];
    design.u.col(i) << at_one[1] - at_zero[1], at_one[0] - at_zero[0];
  }
  return design;
}

ResidualMoments ResidualsOf(const ForceMoments& moments,
                            const TestDesign& design, int direction,
                            const Eigen::Vector4d& constants) {
  const double alpha = design.u.row(direction).dot(constants);
  const double beta = design.v.row(direction).dot(constants);
  const Eigen::Matrix3d& c = moments.comoment;
  const int f = 1 + direction;
  ResidualMoments residuals;
  residuals.mean_n = moments.mean[f] - alpha * moments.mean[0] - beta;
  residuals.scatter_n2 =
      std::max(0.0, c(f, f) - 2.0 * alpha * c(0, f) + alpha * alpha * c(0, 0));
  return residuals;
}

void EvaluateFit(const ForceModel& model, const std::vector<ForceTest>& tests,
                 ForceFitSummary* summary) {
  const Eigen::Vector4d c = ConstantsVector(model.constants);
  std::array<double, 2> residual_sum = {0.0, 0.0};
  std::array<double, 2> min_force = {INFINITY, INFINITY};
  std::array<double, 2> max_force = {-INFINITY, -INFINITY};
  ForceMoments all;
  summary->test_rmse_n.clear();
  for (const ForceTest& test : tests) {
    const TestDesign design =
        DesignOfTest(model, test.delta_length_mm(), test.theta_rad());
    const ForceMoments m = test.statistics.All();
    all.Merge(m);
    std::array<double, 2> test_rmse = {0.0, 0.0};
    for (int d = 0; d < 2; ++d) {
      const double ss = ResidualsOf(m, design, d, c).SumOfSquares(m.count);
      residual_sum[d] += ss;
      test_rmse[d] = m.count > 0 ? std::sqrt(ss / m.count) : NAN;
    }
    summary->test_rmse_n.push_back(test_rmse);
    min_force[kAxial] =
        std::min(min_force[kAxial], test.statistics.min_axial_n);
    max_force[kAxial] =
        std::max(max_force[kAxial], test.statistics.max_axial_n);
    min_force[kShear] =
        std::min(min_force[kShear], test.statistics.min_shear_n);
    max_force[kShear] =
        std::max(max_force[kShear], test.statistics.max_shear_n);
  }
  summary->rows = all.count;
  for (int d = 0; d < 2; ++d) {
    DirectionFit& fit = summary->directions[d];
    const double total = all.comoment(1 + d, 1 + d);
    fit.r_squared = total > 0.0 ? 1.0 - residual_sum[d] / total : NAN;
    fit.rmse_n = all.count > 0 ? std::sqrt(residual_sum[d] / all.count) : NAN;
    fit.full_scale_range_n = max_force[d] - min_force[d];
    fit.rmse_percent_of_range = 100.0 * fit.rmse_n / fit.full_scale_range_n;
  }
}

namespace {

// The normal equations restricted to a model's free constants, the fixed
// constants' contribution moved to the right-hand side, with the column
// scaling that makes their conditioning meaningful.
struct FreeSystem {
  std::vector<int> free;
  Eigen::Vector4d fixed_values;
  Eigen::MatrixXd normal;
  Eigen::VectorXd rhs;
  Eigen::VectorXd scale;   // 1 / sqrt(diag(normal))
  Eigen::MatrixXd scaled;  // scale normal scale

  int size() const { return static_cast<int>(free.size()); }
};

FreeSystem RestrictToFree(const FitModel& fit_model,
                          const NormalEquations& equations) {
  FreeSystem system;
  system.free = FreeIndices(fit_model);
  system.fixed_values = ConstantsVector(fit_model.model.constants);
  system.normal = Restrict(equations.normal, system.free);
  const int k = system.size();
  system.rhs.resize(k);
  for (int i = 0; i < k; ++i) {
    system.rhs[i] = equations.rhs[system.free[i]];
    for (int j = 0; j < kNumFitConstants; ++j) {
      if (!fit_model.free[j]) {
        system.rhs[i] -=
            equations.normal(system.free[i], j) * system.fixed_values[j];
      }
    }
  }
  system.scale = system.normal.diagonal().cwiseSqrt().cwiseInverse();
  system.scaled =
      system.scale.asDiagonal() * system.normal * system.scale.asDiagonal();
  return system;
}

// Identifiability: a constant whose column is zero over every row cannot be
// fitted at all; near-dependent columns make the answer meaningless. Sets
// the condition number; returns why the tests cannot give the constants.
std::optional<std::string> WhyNotIdentifiable(const FreeSystem& system,
                                              const ForceFitOptions& options,
                                              double* condition_number) {
  const int k = system.size();
  const double largest = system.normal.diagonal().maxCoeff();
  for (int i = 0; i < k; ++i) {
    if (!(system.normal(i, i) > 1e-12 * largest)) {
      return fmt::format("{} cannot be fitted from these tests: {}",
                         kFitConstantNames[system.free[i]],
                         kIdentifiabilityHint[system.free[i]]);
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(system.scaled);
  *condition_number =
      eigen.eigenvalues().maxCoeff() / eigen.eigenvalues().minCoeff();
  if (*condition_number <= options.max_condition_number) return std::nullopt;
  const Eigen::VectorXd weakest = eigen.eigenvectors().col(0);
  std::string names;
  for (int i = 0; i < k; ++i) {
    if (std::abs(weakest[i]) > 0.3) {
      names += (names.empty() ? "" : " and ") +
               std::string(kFitConstantNames[system.free[i]]);
    }
  }
  return fmt::format(
      "ill-conditioned (condition number {:.3g}): these tests cannot tell {} "
      "apart; add tests that vary dL and theta independently",
      *condition_number, names);
}

// Each test's design restricted to the free constants, the fixed ones'
// part kept aside.
std::vector<FreeDesign> FreeDesigns(const FitModel& fit_model,
                                    const std::vector<ForceTest>& tests,
                                    const FreeSystem& system) {
  std::vector<FreeDesign> designs;
  for (const ForceTest& test : tests) {
    const TestDesign design =
        DesignOfTest(fit_model.model, test.delta_length_mm(), test.theta_rad());
    FreeDesign& restricted = designs.emplace_back();
    restricted.u.resize(2, system.size());
    restricted.v.resize(2, system.size());
    for (int i = 0; i < system.size(); ++i) {
      restricted.u.col(i) = design.u.col(system.free[i]);
      restricted.v.col(i) = design.v.col(system.free[i]);
    }
    for (int j = 0; j < kNumFitConstants; ++j) {
      if (fit_model.free[j]) continue;
      restricted.fixed_u += design.u.col(j) * system.fixed_values[j];
      restricted.fixed_v += design.v.col(j) * system.fixed_values[j];
    }
  }
  return designs;
}

// The free constants: the closed form, unless a robust loss or the row-wise
// cross-check asks for Ceres on the rows, or the closed form leaves the
// bounds (then Ceres on the normal equations). Sets the method; returns why
// not on failure.
std::optional<std::string> SolveFree(const FitModel& fit_model,
                                     const std::vector<ForceTest>& tests,
                                     const std::vector<ForceRow>& rows,
                                     const FreeSystem& system,
                                     const ForceFitOptions& options,
                                     Eigen::VectorXd* values,
                                     ForceFitSummary* summary) {
  const Eigen::VectorXd closed_form =
      system.scale.asDiagonal() *
      system.scaled.ldlt().solve(system.scale.asDiagonal() * system.rhs);
  const Eigen::VectorXd lower = LowerBounds(system.free, options);
  *values = closed_form;
  summary->method = "closed form (normal equations)";
  const bool robust = options.loss != FitLoss::kLeastSquares;
  CeresFitResult result;
  if (robust || options.rows_with_ceres) {
    if (rows.empty()) {
      return "a robust or row-wise fit needs rows kept in memory "
             "(keep_every_nth_row > 0)";
    }
    // Algorithm 1 starts from [1 1 1 1]; a robust fit starts from the least-
    // squares answer, which is the right basin for a non-convex loss.
    result =
        SolveRows(FreeDesigns(fit_model, tests, system), rows, options, lower,
                  robust ? closed_form : Eigen::VectorXd::Ones(system.size()));
    const char* loss_name = options.loss == FitLoss::kHuber    ? "Huber"
                            : options.loss == FitLoss::kCauchy ? "Cauchy"
                                                               : "no";
    summary->method =
        fmt::format("Ceres on {} rows, {} loss{}", rows.size(), loss_name,
                    robust ? fmt::format(" (scale {} N)", options.loss_scale_n)
                           : std::string());
  } else if ((closed_form.array() < lower.array()).any()) {
    result = SolveBoundedNormalEquations(system.normal, system.rhs, lower,
                                         closed_form);
    summary->method = "Ceres, bounded least squares (normal equations)";
  } else {
    return std::nullopt;
  }
  if (!result.converged) return result.why_not;
  *values = result.values;
  summary->ceres_iterations = result.iterations;
  return std::nullopt;
}

// Each test's score, sum over its rows and directions of w_d^2 a r (the
// gradient of its share of the objective, restricted to the free
// constants), exactly from its moments: with r = F - a . c and a = P u + v,
// sum a r = u (C_PF - alpha C_PP + n P̄ r̄) + v n r̄, alpha = u . c.
std::vector<Eigen::VectorXd> TestScores(const ForceModel& fitted,
                                        const std::vector<ForceTest>& tests,
                                        const FreeSystem& system,
                                        const ForceFitOptions& options) {
  const Eigen::Vector4d c = ConstantsVector(fitted.constants);
  const std::array<double, 2> weights = {options.axial_weight,
                                         options.shear_weight};
  std::vector<Eigen::VectorXd> scores;
  for (const ForceTest& test : tests) {
    const ForceMoments m = test.statistics.All();
    if (m.count == 0) continue;
    const TestDesign design =
        DesignOfTest(fitted, test.delta_length_mm(), test.theta_rad());
    const double n = static_cast<double>(m.count);
    Eigen::Vector4d score = Eigen::Vector4d::Zero();
    for (int d = 0; d < 2; ++d) {
      const Eigen::Vector4d u = design.u.row(d).transpose();
      const Eigen::Vector4d v = design.v.row(d).transpose();
      const double alpha = u.dot(c);
      const double mean_residual = ResidualsOf(m, design, d, c).mean_n;
      const double sum_pr = m.comoment(0, 1 + d) - alpha * m.comoment(0, 0) +
                            n * m.mean[0] * mean_residual;
      score += weights[d] * weights[d] * (u * sum_pr + v * n * mean_residual);
    }
    Eigen::VectorXd restricted(system.size());
    for (int i = 0; i < system.size(); ++i) {
      restricted[i] = score[system.free[i]];
    }
    scores.push_back(restricted);
  }
  return scores;
}

// Standard errors, the larger of two estimates for each constant:
// - from the rows' noise, one level per direction (axial and shear sensors
//   differ): Cov = N^-1 (sum_d w_d^4 s_d^2 N_d) N^-1, right when every row's
//   residual is independent noise;
// - from the tests' scatter (the sandwich estimator clustered by test):
//   Cov = T / (T - k) N^-1 (sum_t g_t g_t^T) N^-1 with g_t each test's
//   score, right when what differs from test to test (a clamp a little off
//   its measured configuration, hysteresis, the model's misfit at that
//   configuration) is independent between tests but shared by its rows.
// On the synthetic protocol with every imperfection on, the first gave
// A_z to +-0.015 mm^2 while six seeds scattered by 1.1 mm^2
// (docs/characterisation.md): the rows of one test are not independent
// evidence. The second needs more tests than constants.
void SetStandardErrors(const FreeSystem& system,
                       const NormalEquations& equations,
                       const std::vector<Eigen::VectorXd>& scores,
                       const ForceFitOptions& options,
                       ForceFitSummary* summary) {
  const int k = system.size();
  const double dof = static_cast<double>(summary->rows - k);
  if (dof <= 0) return;
  const Eigen::MatrixXd inverse =
      system.scale.asDiagonal() *
      system.scaled.ldlt().solve(Eigen::MatrixXd(system.scale.asDiagonal()));
  Eigen::MatrixXd middle = Eigen::MatrixXd::Zero(k, k);
  const std::array<double, 2> weights = {options.axial_weight,
                                         options.shear_weight};
  for (int d = 0; d < 2; ++d) {
    const double variance = summary->directions[d].rmse_n *
                            summary->directions[d].rmse_n *
                            static_cast<double>(summary->rows) / dof;
    middle += std::pow(weights[d], 4) * variance *
              Restrict(equations.direction_normal[d], system.free);
  }
  const Eigen::MatrixXd from_rows = inverse * middle * inverse;
  const int tests = static_cast<int>(scores.size());
  Eigen::MatrixXd from_tests = Eigen::MatrixXd::Zero(k, k);
  if (tests > k) {
    Eigen::MatrixXd outer = Eigen::MatrixXd::Zero(k, k);
    for (const Eigen::VectorXd& g : scores) outer += g * g.transpose();
    from_tests =
        static_cast<double>(tests) / (tests - k) * inverse * outer * inverse;
  } else {
    summary->standard_errors_caveat = fmt::format(
        "{} tests for {} constants, so their scatter cannot be measured: ± "
        "is the rows' noise alone, which understates it where a test's rows "
        "share its clamp or the model's misfit; add tests",
        tests, k);
  }
  for (int i = 0; i < k; ++i) {
    summary->row_noise_standard_errors[system.free[i]] =
        std::sqrt(from_rows(i, i));
    summary->standard_errors[system.free[i]] =
        std::sqrt(std::max(from_rows(i, i), from_tests(i, i)));
  }
}

// Constants at their bounds are listed (no standard error); one whose
// standard error is too large for its value is not determined by the tests.
std::optional<std::string> WhyNotDetermined(const FreeSystem& system,
                                            const Eigen::VectorXd& values,
                                            const ForceFitOptions& options,
                                            ForceFitSummary* summary) {
  const Eigen::VectorXd lower = LowerBounds(system.free, options);
  for (int i = 0; i < system.size(); ++i) {
    const int index = system.free[i];
    if (values[i] <= lower[i]) {
      summary->at_bounds.emplace_back(kFitConstantNames[index]);
      summary->standard_errors[index] = NAN;
      summary->row_noise_standard_errors[index] = NAN;
    } else if (summary->standard_errors[index] >
               options.max_relative_standard_error * std::abs(values[i])) {
      return fmt::format(
          "{} is not determined by these tests: {:.4g} +- {:.3g} (standard "
          "error above {:.0f} % of the value): {}",
          kFitConstantNames[index], values[i], summary->standard_errors[index],
          100.0 * options.max_relative_standard_error,
          kIdentifiabilityHint[index]);
    }
  }
  return std::nullopt;
}

}  // namespace

ForceFitSummary FitForceModel(const FitModel& fit_model,
                              const std::vector<ForceTest>& tests,
                              const std::vector<ForceRow>& rows,
                              const ForceFitOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  ForceFitSummary summary;
  summary.model_name = fit_model.name;
  const NormalEquations equations =
      AccumulateNormalEquations(fit_model.model, tests, options);
  const FreeSystem system = RestrictToFree(fit_model, equations);
  if (auto why =
          WhyNotIdentifiable(system, options, &summary.condition_number)) {
    summary.why_not = *why;
    return summary;
  }
  Eigen::VectorXd values;
  if (auto why = SolveFree(fit_model, tests, rows, system, options, &values,
                           &summary)) {
    summary.why_not = *why;
    return summary;
  }
  Eigen::Vector4d all_values = system.fixed_values;
  for (int i = 0; i < system.size(); ++i)
    all_values[system.free[i]] = values[i];
  ForceModel fitted = fit_model.model;
  fitted.constants = ConstantsFromVector(all_values, fit_model.model.constants);
  summary.constants = fitted.constants;
  EvaluateFit(fitted, tests, &summary);
  SetStandardErrors(system, equations,
                    TestScores(fitted, tests, system, options), options,
                    &summary);
  if (auto why = WhyNotDetermined(system, values, options, &summary)) {
    summary.why_not = *why;
    return summary;
  }
  summary.ok = true;
  return summary;
}

}  // namespace softbench
