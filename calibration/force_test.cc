#include "calibration/force_test.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "model/units.h"

namespace softbench {

std::optional<std::string> ForceBinningOptions::Problem() const {
  if (!(zero_pressure_mpa >= 0.0) || !std::isfinite(zero_pressure_mpa)) {
    return "zero_pressure_mpa must be a finite number >= 0";
  }
  if (!(ramp_drop_mpa > 0.0) || !std::isfinite(ramp_drop_mpa)) {
    return "ramp_drop_mpa must be a finite number > 0";
  }
  if (!(bin_width_mpa > 0.0) || !std::isfinite(bin_width_mpa)) {
    return "bin_width_mpa must be a finite number > 0";
  }
  return std::nullopt;
}

ForceMoments ForceTestStatistics::Phase(RampPhase phase) const {
  ForceMoments merged;
  for (const ForceMoments& bin : bins[static_cast<int>(phase)]) {
    merged.Merge(bin);
  }
  return merged;
}

ForceMoments ForceTestStatistics::All() const {
  ForceMoments merged = Phase(RampPhase::kUp);
  merged.Merge(Phase(RampPhase::kDown));
  return merged;
}

ForceMoments ForceTestStatistics::ZeroPressure() const {
  ForceMoments merged;
  for (const std::vector<ForceMoments>& phase : bins) {
    if (!phase.empty()) merged.Merge(phase.front());
  }
  return merged;
}

ForceTestAccumulator::ForceTestAccumulator(const ForceBinningOptions& options)
    : options_(options), inverse_bin_width_(1.0 / options.bin_width_mpa) {}

void ForceTestAccumulator::Add(double pressure_mpa, double axial_n,
                               double shear_n) {
  if (count_ == 0) {
    min_axial_n_ = max_axial_n_ = axial_n;
    min_shear_n_ = max_shear_n_ = shear_n;
    max_pressure_mpa_ = pressure_mpa;
  }
  ++count_;
  min_axial_n_ = std::min(min_axial_n_, axial_n);
  max_axial_n_ = std::max(max_axial_n_, axial_n);
  min_shear_n_ = std::min(min_shear_n_, shear_n);
  max_shear_n_ = std::max(max_shear_n_, shear_n);
  max_pressure_mpa_ = std::max(max_pressure_mpa_, pressure_mpa);
  if (pressure_mpa < max_pressure_mpa_ - options_.ramp_drop_mpa) {
    phase_ = RampPhase::kDown;
  }
  size_t bin = 0;
  if (pressure_mpa > options_.zero_pressure_mpa) {
    bin = 1 + static_cast<size_t>((pressure_mpa - options_.zero_pressure_mpa) *
                                  inverse_bin_width_);
  }
  std::vector<ForceMomentAccumulator>& bins = bins_[static_cast<int>(phase_)];
  if (bin >= bins.size()) bins.resize(bin + 1);
  bins[bin].Add(pressure_mpa, axial_n, shear_n);
}

ForceTestStatistics ForceTestAccumulator::Statistics() const {
  ForceTestStatistics statistics;
  for (int phase = 0; phase < kNumRampPhases; ++phase) {
    for (const ForceMomentAccumulator& bin : bins_[phase]) {
      statistics.bins[phase].push_back(bin.Moments());
    }
  }
  statistics.min_axial_n = min_axial_n_;
  statistics.max_axial_n = max_axial_n_;
  statistics.min_shear_n = min_shear_n_;
  statistics.max_shear_n = max_shear_n_;
  statistics.max_pressure_mpa = max_pressure_mpa_;
  return statistics;
}

std::optional<std::string> ImplausibleConfiguration(double delta_length_mm,
                                                    double theta_deg) {
  if (std::abs(theta_deg) >= 90.0) {
    return fmt::format(
        "a bend of {:g} deg folds the actuator back past its clamp; give the "
        "angle in degrees, within -90..90",
        theta_deg);
  }
  if (std::abs(delta_length_mm) >= 100.0) {
    return fmt::format(
        "a length change of {:g} mm is beyond any bellows actuator; give it "
        "in millimetres",
        delta_length_mm);
  }
  return std::nullopt;
}

std::optional<std::string> ImplausibleTest(const ForceTest& test) {
  if (auto problem = ImplausibleConfiguration(
          test.nominal_delta_length_mm, RadToDeg(test.nominal_theta_rad))) {
    return problem;
  }
  if (auto problem = ImplausibleConfiguration(test.delta_length_mm(),
                                              RadToDeg(test.theta_rad()))) {
    return "measured: " + *problem;
  }
  return std::nullopt;
}

}  // namespace softbench
