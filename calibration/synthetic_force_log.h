#ifndef SOFTBENCH_CALIBRATION_SYNTHETIC_FORCE_LOG_H_
#define SOFTBENCH_CALIBRATION_SYNTHETIC_FORCE_LOG_H_

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "model/actuator_model.h"

namespace softbench {

// The thesis's characterisation protocol (section 3.2): each configuration
// (dL, theta) is tested `repeats` times; the pressure steps from 0 to the top
// and back down, each level held `hold_s`.
struct ForceProtocol {
  struct Configuration {
    double delta_length_mm = 0.0;
    double theta_rad = 0.0;
  };
  std::vector<Configuration> configurations;
  int repeats = 2;
  double step_up_mpa = 0.00276;
  double step_down_mpa = 0.00414;
  double top_mpa = 0.0414;
  double hold_s = 3.0;

  // 27 configurations x 2 repeats: dL in {-2..2} mm x theta in {0, 10, 18,
  // 25, 30} deg, plus dL = +-3 mm at theta = 0.
  static ForceProtocol Thesis();
  // The held pressure levels of one test, in order: 0, up to the top, down
  // to 0.
  std::vector<double> Levels() const;
  std::optional<std::string> Problem() const;
};

// A synthetic force/torque log from known constants, with the imperfections
// of the thesis's rig, each of which can be switched off (zero).
struct SyntheticForceLogOptions {
  ForceModel model;  // the truth
  ForceProtocol protocol = ForceProtocol::Thesis();
  double sample_rate_hz = 5700.0;  // the thesis's scale: ~24 million rows
  uint64_t seed = 1;
  // Sensor noise, 1 sigma [N]: the Mini40's 95 % uncertainty, 0.75 % of
  // 120 N axial and 1.25 % of 40 N shear (thesis 3.1.2), over 1.96.
  double axial_noise_n = 0.0075 * 120.0 / 1.96;
  double shear_noise_n = 0.0125 * 40.0 / 1.96;
  double torque_noise_nm = 0.002;
  // Pressure sensor noise [MPa]: 0.25 % of its 103.42 kPa range, over 1.96.
  double pressure_noise_mpa = 0.0025 * 0.10342 / 1.96;
  // First-order regulator: settles to 1 % in 4.6 tau = 0.37 s (< 0.4 s,
  // thesis 3.2).
  double regulator_time_constant_s = 0.08;
  // Configuration errors, 1 sigma: the clamped configuration differs from
  // the nominal one (the thesis measured 0.04 mm and 0.18 deg mean errors).
  double delta_length_error_mm = 0.04;
  double theta_error_rad = 0.0031;
  // A_z in compression (dL < 0) is this times A_z in extension (fig. 3.17a).
  double compression_area_factor = 1.15;
  // Force added on the way down (viscous lag of the bellows) [N].
  double hysteresis_axial_n = 0.3;
  double hysteresis_shear_n = 0.1;
  // Fraction of rows whose forces are replaced by gross outliers, uniform in
  // +-outlier_n.
  double outlier_fraction = 0.0;
  double outlier_n = 50.0;

  // Only sensor noise: the model is then exactly right.
  static SyntheticForceLogOptions NoiseOnly(const ForceModel& model);
  std::optional<std::string> Problem() const;
};

// One test of the synthetic protocol.
struct SyntheticTest {
  std::string id;  // "t01" ...
  double nominal_delta_length_mm = 0.0;
  double nominal_theta_rad = 0.0;
  double delta_length_mm = 0.0;  // as clamped (nominal + error)
  double theta_rad = 0.0;
  int64_t rows = 0;
};

// One row as a six-axis sensor logs it: the actuator's axial force on +z,
// shear on +y.
struct SyntheticRow {
  double time_s = 0.0;
  double pressure_mpa = 0.0;              // as the pressure sensor reads it
  double force_n[3] = {0.0, 0.0, 0.0};    // Fx, Fy, Fz
  double torque_nm[3] = {0.0, 0.0, 0.0};  // Tx, Ty, Tz
};

// The tests of the protocol with their (seeded) configuration errors.
std::vector<SyntheticTest> SyntheticTests(
    const SyntheticForceLogOptions& options);

// Calls `emit` for every row of test `index`, in time order. Each test has
// its own random stream, so tests can be generated in parallel and any one
// reproduced alone.
void GenerateSyntheticTest(
    const SyntheticForceLogOptions& options, const SyntheticTest& test,
    int index, const std::function<void(const SyntheticRow&)>& emit);

}  // namespace softbench

#endif  // SOFTBENCH_CALIBRATION_SYNTHETIC_FORCE_LOG_H_
