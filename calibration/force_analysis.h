#ifndef SOFTBENCH_CALIBRATION_FORCE_ANALYSIS_H_
#define SOFTBENCH_CALIBRATION_FORCE_ANALYSIS_H_

#include <Eigen/Core>
#include <vector>

#include "calibration/force_test.h"

namespace softbench {

// The per-configuration quantities of thesis section 3.3, before any model:
// repeats of one nominal (dL, theta) pooled.
struct ConfigurationAnalysis {
  double nominal_delta_length_mm = 0.0;
  double nominal_theta_rad = 0.0;
  // Mean of the tests' configurations (measured where given).
  double delta_length_mm = 0.0;
  double theta_rad = 0.0;
  std::vector<int> tests;  // indices into the test list
  // Static offset: mean force at zero pressure (figs. 3.15, 3.16, 3.18),
  // (axial, shear) [N], and the largest difference between repeats.
  Eigen::Vector2d static_offset_n = Eigen::Vector2d::Zero();
  Eigen::Vector2d static_offset_spread_n = Eigen::Vector2d::Zero();
  // Effective areas (fig. 3.17): axial dF_z/dP, and shear -dF_y/dP (= W_y
  // theta in the model) [mm^2], pooled within tests.
  double axial_area_mm2 = 0.0;
  double shear_area_mm2 = 0.0;
  // Hysteresis: the up-ramp force-pressure line minus the down-ramp line
  // (axial, shear) [N]: its largest magnitude over [0, top pressure], and its
  // signed mean over that range.
  Eigen::Vector2d hysteresis_max_n = Eigen::Vector2d::Zero();
  Eigen::Vector2d hysteresis_mean_n = Eigen::Vector2d::Zero();
};

// Groups tests by nominal configuration, in order of first appearance.
std::vector<ConfigurationAnalysis> AnalyseConfigurations(
    const std::vector<ForceTest>& tests);

// Slope and intercept of force against pressure in direction d (0 axial,
// 1 shear) from moments; NaN slope when the pressure never varies.
Eigen::Vector2d ForcePressureLine(const ForceMoments& moments, int direction);

}  // namespace softbench

#endif  // SOFTBENCH_CALIBRATION_FORCE_ANALYSIS_H_
