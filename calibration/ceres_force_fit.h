#ifndef SOFTBENCH_CALIBRATION_CERES_FORCE_FIT_H_
#define SOFTBENCH_CALIBRATION_CERES_FORCE_FIT_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "calibration/force_fit.h"

namespace softbench {

// The fits that are not plain least squares, solved with Ceres over the free
// constants only (fixed ones are folded into the designs' offsets).
struct CeresFitResult {
  bool converged = false;
  std::string why_not;
  Eigen::VectorXd values;  // the free constants
  int iterations = 0;
};

// Least squares with lower bounds, exactly: with N = L L^T,
// |L^T c - L^{-1} b|^2 = c^T N c - 2 b^T c + const, the rows' objective.
CeresFitResult SolveBoundedNormalEquations(const Eigen::MatrixXd& normal,
                                           const Eigen::VectorXd& rhs,
                                           const Eigen::VectorXd& lower,
                                           const Eigen::VectorXd& start);

// One free-constant design per test: F_d = (P u_d + v_d) . c + offset_d(P).
struct FreeDesign {
  Eigen::Matrix<double, 2, Eigen::Dynamic> u;
  Eigen::Matrix<double, 2, Eigen::Dynamic> v;
  Eigen::Vector2d fixed_u = Eigen::Vector2d::Zero();  // fixed constants' part
  Eigen::Vector2d fixed_v = Eigen::Vector2d::Zero();
};

// Fits the rows one residual block each (axial and shear residuals, weighted),
// with the options' loss and bounds.
CeresFitResult SolveRows(const std::vector<FreeDesign>& designs,
                         const std::vector<ForceRow>& rows,
                         const ForceFitOptions& options,
                         const Eigen::VectorXd& lower,
                         const Eigen::VectorXd& start);

}  // namespace softbench

#endif  // SOFTBENCH_CALIBRATION_CERES_FORCE_FIT_H_
