#include "calibration/force_analysis.h"

#include <cmath>

namespace softbench {

Eigen::Vector2d ForcePressureLine(const ForceMoments& moments, int direction) {
  const double slope =
      moments.comoment(0, 0) > 0.0
          ? moments.comoment(0, 1 + direction) / moments.comoment(0, 0)
          : NAN;
  return {slope, moments.mean[1 + direction] - slope * moments.mean[0]};
}

std::vector<ConfigurationAnalysis> AnalyseConfigurations(
    const std::vector<ForceTest>& tests) {
  std::vector<ConfigurationAnalysis> configurations;
  for (int t = 0; t < static_cast<int>(tests.size()); ++t) {
    const ForceTest& test = tests[t];
    ConfigurationAnalysis* match = nullptr;
    for (ConfigurationAnalysis& configuration : configurations) {
      if (std::abs(configuration.nominal_delta_length_mm -
                   test.nominal_delta_length_mm) < 1e-9 &&
          std::abs(configuration.nominal_theta_rad - test.nominal_theta_rad) <
              1e-12) {
        match = &configuration;
      }
    }
    if (match == nullptr) {
      match = &configurations.emplace_back();
      match->nominal_delta_length_mm = test.nominal_delta_length_mm;
      match->nominal_theta_rad = test.nominal_theta_rad;
    }
    match->tests.push_back(t);
  }

  for (ConfigurationAnalysis& configuration : configurations) {
    const double count = static_cast<double>(configuration.tests.size());
    Eigen::Vector2d offset_min = Eigen::Vector2d::Constant(INFINITY);
    Eigen::Vector2d offset_max = Eigen::Vector2d::Constant(-INFINITY);
    ForceMoments zero;
    Eigen::Vector3d pooled = Eigen::Vector3d::Zero();  // C_PP, C_PFa, C_PFs
    for (int t : configuration.tests) {
      const ForceTest& test = tests[t];
      configuration.delta_length_mm += test.delta_length_mm() / count;
      configuration.theta_rad += test.theta_rad() / count;
      const ForceMoments test_zero = test.statistics.ZeroPressure();
      zero.Merge(test_zero);
      offset_min = offset_min.cwiseMin(test_zero.mean.tail<2>());
      offset_max = offset_max.cwiseMax(test_zero.mean.tail<2>());
      const ForceMoments all = test.statistics.All();
      pooled += all.comoment.row(0).transpose();
      const double top = test.statistics.max_pressure_mpa;
      for (int d = 0; d < 2; ++d) {
        const Eigen::Vector2d up =
            ForcePressureLine(test.statistics.Phase(RampPhase::kUp), d);
        const Eigen::Vector2d down =
            ForcePressureLine(test.statistics.Phase(RampPhase::kDown), d);
        // The gap is affine in P: extremes at the ends, mean at mid-range.
        const double gap_at_zero = up[1] - down[1];
        const double gap_at_top = gap_at_zero + (up[0] - down[0]) * top;
        configuration.hysteresis_max_n[d] +=
            std::max(std::abs(gap_at_zero), std::abs(gap_at_top)) / count;
        configuration.hysteresis_mean_n[d] +=
            0.5 * (gap_at_zero + gap_at_top) / count;
      }
    }
    configuration.static_offset_n = zero.mean.tail<2>();
    configuration.static_offset_spread_n = offset_max - offset_min;
    configuration.axial_area_mm2 = pooled[1] / pooled[0];
    configuration.shear_area_mm2 = -pooled[2] / pooled[0];
  }
  return configurations;
}

}  // namespace softbench
