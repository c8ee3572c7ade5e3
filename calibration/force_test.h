#ifndef SOFTBENCH_CALIBRATION_FORCE_TEST_H_
#define SOFTBENCH_CALIBRATION_FORCE_TEST_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "calibration/force_moments.h"

namespace softbench {

// The two halves of the thesis's pressure protocol (section 3.2): stepped up
// from zero to the top pressure, then stepped down to zero.
enum class RampPhase { kUp = 0, kDown = 1 };
inline constexpr int kNumRampPhases = 2;

// How one test's rows are grouped while they stream past.
struct ForceBinningOptions {
  // Rows at or below this pressure are zero-pressure rows, whose mean force is
  // the configuration's static offset (thesis figs. 3.15, 3.16). Above the
  // pressure sensor's noise (0.26 kPa at 95 %), below the first step (2.76).
  double zero_pressure_mpa = 0.0005;
  // The ramp turns from up to down once the pressure falls this far below the
  // highest pressure so far: above noise and regulator overshoot, below the
  // first down step (4.14 kPa).
  double ramp_drop_mpa = 0.002;
  // Width of the pressure bins kept for plots and residuals by pressure.
  double bin_width_mpa = 0.001;

  // Empty when usable; otherwise names the bad field.
  std::optional<std::string> Problem() const;
};

// What a fit needs of one test's rows: centred moments per ramp phase and
// pressure bin (bin 0: zero-pressure rows; bin k >= 1: rows with pressure in
// (zero + (k - 1) w, zero + k w]), and the extremes of the forces.
struct ForceTestStatistics {
  std::array<std::vector<ForceMoments>, kNumRampPhases> bins;
  double min_axial_n = 0.0, max_axial_n = 0.0;
  double min_shear_n = 0.0, max_shear_n = 0.0;
  double max_pressure_mpa = 0.0;

  ForceMoments Phase(RampPhase phase) const;
  ForceMoments All() const;
  // Both phases' zero-pressure rows (before the ramp and after it).
  ForceMoments ZeroPressure() const;
};

// Accumulates one test's rows in time order.
class ForceTestAccumulator {
 public:
  explicit ForceTestAccumulator(const ForceBinningOptions& options);

  void Add(double pressure_mpa, double axial_n, double shear_n);
  int64_t count() const { return count_; }
  ForceTestStatistics Statistics() const;

 private:
  ForceBinningOptions options_;
  double inverse_bin_width_;
  std::array<std::vector<ForceMomentAccumulator>, kNumRampPhases> bins_;
  RampPhase phase_ = RampPhase::kUp;
  int64_t count_ = 0;
  double max_pressure_mpa_ = 0.0;
  double min_axial_n_ = 0.0, max_axial_n_ = 0.0;
  double min_shear_n_ = 0.0, max_shear_n_ = 0.0;
};

// One characterisation test: an actuator clamped at (dL, theta) while the
// pressure ramps up and down (thesis section 3.2).
struct ForceTest {
  std::string id;
  std::string source;  // the file its rows came from, for messages
  double nominal_delta_length_mm = 0.0;
  double nominal_theta_rad = 0.0;
  // The configuration as measured on the rig (the thesis measured it with
  // mean errors of 0.04 mm and 0.18 deg); the fit uses it when given.
  std::optional<double> measured_delta_length_mm;
  std::optional<double> measured_theta_rad;
  ForceTestStatistics statistics;

  double delta_length_mm() const {
    return measured_delta_length_mm.value_or(nominal_delta_length_mm);
  }
  double theta_rad() const {
    return measured_theta_rad.value_or(nominal_theta_rad);
  }
};

// Why (dL [mm], theta [deg]) cannot be where a test clamped the actuator, or
// nothing: a bend of 90 deg or more folds the actuator back past its clamp,
// where the model's geometry (Eq. 2.16-3.3) means nothing, and a stretch of
// 100 mm or more is a unit slip (micrometres?) for a bellows about 18.5 mm
// long. The thesis tests -3..3 mm and 0..30 deg (section 3.2; parts failed
// beyond 50 deg).
std::optional<std::string> ImplausibleConfiguration(double delta_length_mm,
                                                    double theta_deg);

// ImplausibleConfiguration of a test's nominal configuration and, where
// given, its measured one (a wrong unit in either is refused, even where
// the fit uses only the other).
std::optional<std::string> ImplausibleTest(const ForceTest& test);

}  // namespace softbench

#endif  // SOFTBENCH_CALIBRATION_FORCE_TEST_H_
