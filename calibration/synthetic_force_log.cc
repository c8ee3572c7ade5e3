#include "calibration/synthetic_force_log.h"

#include <fmt/format.h>

#include <cmath>
#include <random>

#include "model/units.h"

namespace softbench {

ForceProtocol ForceProtocol::Thesis() {
  ForceProtocol protocol;
  for (double dl : {-2.0, -1.0, 0.0, 1.0, 2.0}) {
    for (double theta_deg : {0.0, 10.0, 18.0, 25.0, 30.0}) {
      protocol.configurations.push_back({dl, DegToRad(theta_deg)});
    }
  }
  protocol.configurations.push_back({-3.0, 0.0});
  protocol.configurations.push_back({3.0, 0.0});
  return protocol;
}

std::vector<double> ForceProtocol::Levels() const {
  // Levels are whole multiples of the steps, counted so that rounding never
  // adds or drops a level.
  std::vector<double> levels;
  const int up = static_cast<int>(std::lround(top_mpa / step_up_mpa));
  for (int i = 0; i <= up; ++i) levels.push_back(i * step_up_mpa);
  const int down = static_cast<int>(std::lround(top_mpa / step_down_mpa));
  for (int i = down - 1; i >= 0; --i) levels.push_back(i * step_down_mpa);
  return levels;
}

std::optional<std::string> ForceProtocol::Problem() const {
  if (configurations.empty()) return "the protocol has no configurations";
  if (repeats < 1) return "repeats must be >= 1";
  if (!(step_up_mpa > 0.0) || !(step_down_mpa > 0.0) || !(top_mpa > 0.0)) {
    return "pressure steps and top must be > 0";
  }
  if (!(hold_s > 0.0)) return "hold must be > 0 s";
  return std::nullopt;
}

SyntheticForceLogOptions SyntheticForceLogOptions::NoiseOnly(
    const ForceModel& model) {
  SyntheticForceLogOptions options;
  options.model = model;
  options.regulator_time_constant_s = 0.0;
  options.delta_length_error_mm = 0.0;
  options.theta_error_rad = 0.0;
  options.compression_area_factor = 1.0;
  options.hysteresis_axial_n = 0.0;
  options.hysteresis_shear_n = 0.0;
  return options;
}

std::optional<std::string> SyntheticForceLogOptions::Problem() const {
  if (std::optional<std::string> problem = protocol.Problem()) return problem;
  if (std::optional<std::string> problem = model.constants.Problem()) {
    return problem;
  }
  if (!(sample_rate_hz > 0.0) || sample_rate_hz > 1e6) {
    return "sample rate must be in (0, 1e6] Hz";
  }
  for (double sigma : {axial_noise_n, shear_noise_n, torque_noise_nm,
                       pressure_noise_mpa, regulator_time_constant_s,
                       delta_length_error_mm, theta_error_rad, outlier_n}) {
    if (!(sigma >= 0.0) || !std::isfinite(sigma)) {
      return "noise levels, errors and time constants must be finite and >= 0";
    }
  }
  // A bellows' area in compression differs from its area in extension by
  // tens of per cent, not by orders of magnitude.
  if (!(compression_area_factor > 0.0 && compression_area_factor <= 10.0)) {
    return "compression area factor must be > 0 and at most 10";
  }
  if (!(outlier_fraction >= 0.0 && outlier_fraction <= 1.0)) {
    return "outlier fraction must be in [0, 1]";
  }
  return std::nullopt;
}

std::vector<SyntheticTest> SyntheticTests(
    const SyntheticForceLogOptions& options) {
  std::mt19937_64 random(options.seed);
  std::normal_distribution<double> normal;
  const double duration_s =
      options.protocol.hold_s * options.protocol.Levels().size();
  const int64_t rows = std::llround(duration_s * options.sample_rate_hz);
  std::vector<SyntheticTest> tests;
  for (int repeat = 0; repeat < options.protocol.repeats; ++repeat) {
    for (const ForceProtocol::Configuration& configuration :
         options.protocol.configurations) {
      SyntheticTest& test = tests.emplace_back();
      test.id = fmt::format("t{:02d}", tests.size());
      test.nominal_delta_length_mm = configuration.delta_length_mm;
      test.nominal_theta_rad = configuration.theta_rad;
      test.delta_length_mm = configuration.delta_length_mm +
                             options.delta_length_error_mm * normal(random);
      test.theta_rad =
          configuration.theta_rad + options.theta_error_rad * normal(random);
      test.rows = rows;
    }
  }
  return tests;
}

void GenerateSyntheticTest(
    const SyntheticForceLogOptions& options, const SyntheticTest& test,
    int index, const std::function<void(const SyntheticRow&)>& emit) {
  std::mt19937_64 random(options.seed * 1000003ULL + 7919ULL * (index + 1));
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  ForceModel model = options.model;
  if (test.delta_length_mm < 0.0) {
    model.constants.axial_area_mm2 *= options.compression_area_factor;
  }
  const Deformation deformation{test.delta_length_mm, test.theta_rad};
  const std::vector<double> levels = options.protocol.Levels();
  const int64_t rows_per_hold =
      std::llround(options.protocol.hold_s * options.sample_rate_hz);
  const double dt = 1.0 / options.sample_rate_hz;
  // Fraction of the remaining step the regulator closes per sample.
  const double approach =
      options.regulator_time_constant_s > 0.0
          ? 1.0 - std::exp(-dt / options.regulator_time_constant_s)
          : 1.0;
  const size_t top_level = static_cast<size_t>(
      std::lround(options.protocol.top_mpa / options.protocol.step_up_mpa));
  double pressure_mpa = 0.0;
  int64_t row_index = 0;
  SyntheticRow row;
  for (size_t level = 0; level < levels.size(); ++level) {
    const bool down = level > top_level;
    for (int64_t i = 0; i < rows_per_hold && row_index < test.rows; ++i) {
      pressure_mpa += approach * (levels[level] - pressure_mpa);
      // force_in_local_n is (F_y, F_z).
      const Eigen::Vector2d force =
          EvaluateActuatorForce(model, pressure_mpa, deformation)
              .force_in_local_n;
      double axial = force[1] + options.axial_noise_n * normal(random);
      double shear = force[0] + options.shear_noise_n * normal(random);
      if (down) {
        axial += options.hysteresis_axial_n;
        shear += options.hysteresis_shear_n;
      }
      if (options.outlier_fraction > 0.0 &&
          0.5 * (uniform(random) + 1.0) < options.outlier_fraction) {
        axial = options.outlier_n * uniform(random);
        shear = options.outlier_n * uniform(random);
      }
      row.time_s = static_cast<double>(row_index) * dt;
      row.pressure_mpa =
          pressure_mpa + options.pressure_noise_mpa * normal(random);
      row.force_n[0] = options.shear_noise_n * normal(random);
      row.force_n[1] = shear;
      row.force_n[2] = axial;
      for (double& torque : row.torque_nm) {
        torque = options.torque_noise_nm * normal(random);
      }
      emit(row);
      ++row_index;
    }
  }
}

}  // namespace softbench
