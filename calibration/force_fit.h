#ifndef SOFTBENCH_CALIBRATION_FORCE_FIT_H_
#define SOFTBENCH_CALIBRATION_FORCE_FIT_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "calibration/force_log_reader.h"
#include "calibration/force_test.h"
#include "model/actuator_model.h"

namespace softbench {

// The fitted constants in a fixed order: A_z, W_y, k_s, k_theta.
inline constexpr int kNumFitConstants = 4;
inline constexpr std::array<const char*, kNumFitConstants> kFitConstantNames = {
    "A_z", "W_y", "k_s", "k_theta"};
Eigen::Vector4d ConstantsVector(const ActuatorConstants& constants);
// `base` supplies L0, which is not fitted.
ActuatorConstants ConstantsFromVector(const Eigen::Vector4d& values,
                                      const ActuatorConstants& base);

// A model whose constants are fitted: a force model (its constants give the
// values of fixed constants and L0) and which of the four constants are free.
struct FitModel {
  std::string name;  // "small-angle", "full-trig", "variable-arm", ...
  ForceModel model;
  std::array<bool, kNumFitConstants> free = {true, true, true, true};

  // The thesis's three variants (section 3.3) and the pressurized-spring
  // baseline of [26] (A_z and k_s free, W_y = k_theta = 0).
  static std::vector<FitModel> ThesisModels(const ActuatorConstants& base);
  int NumFree() const;
};

enum class FitLoss { kLeastSquares, kHuber, kCauchy };

struct ForceFitOptions {
  // Weights of axial and shear residuals; Algorithm 1 weighs them equally.
  double axial_weight = 1.0;
  double shear_weight = 1.0;
  // Keep the constants physical (A_z, W_y, k_theta >= 0, k_s > 0): a closed
  // form solution outside is re-solved with Ceres under these bounds.
  bool non_negative = true;
  // A robust loss down-weights gross outliers; it needs the rows in memory
  // (ForceLogReadOptions::keep_every_nth_row) and Ceres.
  FitLoss loss = FitLoss::kLeastSquares;
  // Residual size [N] where the robust loss turns from quadratic to robust:
  // a few times the sensor's noise, well below a gross outlier.
  double loss_scale_n = 1.0;
  // Fit the kept rows with Ceres even without a robust loss, starting from
  // Algorithm 1's [1 1 1 1]: the cross-check of the closed form.
  bool rows_with_ceres = false;
  // Above this condition number of the column-scaled normal matrix the tests
  // cannot separate the constants, and the fit says so instead of answering.
  double max_condition_number = 1e10;
  // A constant whose standard error exceeds this fraction of its value is
  // not determined by the tests; the fit says so instead of printing it.
  double max_relative_standard_error = 0.25;

  std::optional<std::string> Problem() const;
};

// Goodness of fit in one direction, in the thesis's terms (section 3.3).
struct DirectionFit {
  double r_squared = 0.0;
  double rmse_n = 0.0;
  double full_scale_range_n = 0.0;  // max - min of the measured force
  double rmse_percent_of_range = 0.0;
};

enum ForceDirection { kAxial = 0, kShear = 1 };

struct ForceFitSummary {
  bool ok = false;
  std::string why_not;  // when !ok: what is wrong and what to change
  std::string model_name;
  std::string method;  // how the constants were found
  ActuatorConstants constants;
  // 1-sigma standard errors (NaN for fixed constants or ones at a bound):
  // the larger of the rows' noise and the tests' scatter (SetStandardErrors
  // in force_fit.cc), as the rows of one test share its clamp and its
  // misfit.
  Eigen::Vector4d standard_errors = Eigen::Vector4d::Constant(NAN);
  // The rows' noise alone: right only when every row's residual is
  // independent, which the tests' scatter usually shows it is not.
  Eigen::Vector4d row_noise_standard_errors = Eigen::Vector4d::Constant(NAN);
  // Set when the tests' scatter could not be measured (no more tests than
  // free constants): `standard_errors` are then the rows' noise alone.
  std::optional<std::string> standard_errors_caveat;
  std::array<DirectionFit, 2> directions;  // [kAxial], [kShear]
  // RMS residual per test [N], [test][direction].
  std::vector<std::array<double, 2>> test_rmse_n;
  int64_t rows = 0;
  double condition_number = 0.0;
  std::vector<std::string> at_bounds;  // names of constants held at a bound
  int ceres_iterations = 0;
};

// The design of one test: within a configuration every model is affine in P,
//   F_d(P) = (P u_d + v_d) . c,
// with rows d = kAxial, kShear. Derived from EvaluateActuatorForce itself, so
// the fit and the model can never disagree on an equation.
struct TestDesign {
  Eigen::Matrix<double, 2, kNumFitConstants> u;
  Eigen::Matrix<double, 2, kNumFitConstants> v;
};
TestDesign DesignOfTest(const ForceModel& model, double delta_length_mm,
                        double theta_rad);

// The residuals F - model of a group of rows of one test, in direction d,
// exactly from the group's moments: the residual is affine in (P, F) within
// a test, r = F - (P u_d + v_d) . c.
struct ResidualMoments {
  double mean_n = 0.0;
  // Sum over the rows of (r - mean)^2 [N^2].
  double scatter_n2 = 0.0;
  // Sum over the rows of r^2 [N^2].
  double SumOfSquares(int64_t count) const {
    return scatter_n2 + static_cast<double>(count) * mean_n * mean_n;
  }
};
ResidualMoments ResidualsOf(const ForceMoments& moments,
                            const TestDesign& design, int direction,
                            const Eigen::Vector4d& constants);

// Fits `fit_model` to the tests' statistics (and, for robust or row-wise
// fits, to `rows`). Never throws for bad data: an unidentifiable or
// ill-conditioned problem comes back with ok = false and why_not.
ForceFitSummary FitForceModel(const FitModel& fit_model,
                              const std::vector<ForceTest>& tests,
                              const std::vector<ForceRow>& rows,
                              const ForceFitOptions& options);

// Goodness of fit and per-test residuals of given constants, exactly from
// the tests' moments (no second pass over the rows).
void EvaluateFit(const ForceModel& model, const std::vector<ForceTest>& tests,
                 ForceFitSummary* summary);

}  // namespace softbench

#endif  // SOFTBENCH_CALIBRATION_FORCE_FIT_H_
