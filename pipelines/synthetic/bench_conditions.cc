#include "pipelines/synthetic/bench_conditions.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "model/units.h"
#include "util/input_error.h"

namespace softbench {

std::optional<std::string> BenchConditionsOptions::Problem() const {
  if (!drift_px.allFinite() || drift_px.norm() > 50.0) {
    return "camera drift must be finite and at most 50 px";
  }
  if (!(tremor_px >= 0.0 && tremor_px <= 5.0)) {
    return "camera tremor must be 0..5 px RMS";
  }
  for (const CameraBump& b : bumps) {
    if (!(b.time_s >= 0.0) || !b.shift_px.allFinite() ||
        b.shift_px.norm() > 50.0 || !(std::abs(b.roll_deg) <= 2.0)) {
      return "a camera bump needs a time >= 0 s, a shift of at most 50 px "
             "and a roll within +-2 deg";
    }
  }
  if (!(exposure_drift >= 0.0 && exposure_drift < 0.9)) {
    return "exposure drift must be in [0, 0.9)";
  }
  if (!(white_balance_drift_k >= 0.0 && white_balance_drift_k <= 1500.0)) {
    return "white-balance drift must be 0..1500 K";
  }
  if (!(drift_period_s > 0.0 && drift_period_s <= 86400.0)) {
    return "drift period must be > 0 s and at most a day";
  }
  if (!(tag_gone_after_s >= 0.0))
    return "the tag's removal time must be >= 0 s";
  return std::nullopt;
}

namespace {

// A damped step from 0 to 1 that starts at 0 and settles within ~0.1 s (a
// critically damped tripod).
double BumpStep(double since_s) {
  if (since_s <= 0.0) return 0.0;
  const double x = since_s / 0.02;
  return 1.0 - (1.0 + x) * std::exp(-x);
}

}  // namespace

BenchConditions::BenchConditions(const BenchConditionsOptions& options,
                                 const CameraIntrinsics& intrinsics,
                                 double duration_s)
    : options_(options), intrinsics_(intrinsics), duration_s_(duration_s) {
  constexpr int kTones = 6;
  std::mt19937_64 rng(options.seed * 0x2545F4914F6CDD1DULL + 7);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * std::numbers::pi);
  for (int k = 0; k < kTones; ++k) {
    frequencies_hz_.push_back(2.0 + 10.0 * k / (kTones - 1));
    phases_.emplace_back(phase(rng), phase(rng));
  }
  // Each axis is a sum of kTones unit sinusoids (mean square kTones / 2);
  // the two axes together have RMS tremor_px.
  tremor_amplitude_px_ = options.tremor_px / std::sqrt(kTones);
}

FrameConditions BenchConditions::At(double time_s) const {
  FrameConditions c;
  Eigen::Vector2d shift =
      options_.drift_px * std::clamp(time_s / duration_s_, 0.0, 1.0);
  double roll_deg = 0.0;
  for (size_t k = 0; k < frequencies_hz_.size(); ++k) {
    const double w = 2.0 * std::numbers::pi * frequencies_hz_[k] * time_s;
    shift +=
        tremor_amplitude_px_ * Eigen::Vector2d(std::sin(w + phases_[k].x()),
                                               std::sin(w + phases_[k].y()));
  }
  for (const CameraBump& bump : options_.bumps) {
    const double step = BumpStep(time_s - bump.time_s);
    shift += step * bump.shift_px;
    roll_deg += step * bump.roll_deg;
  }
  c.motion =
      CameraMotion::FromImageShift(intrinsics_, shift, DegToRad(roll_deg));
  const double phase =
      2.0 * std::numbers::pi * time_s / options_.drift_period_s;
  // Around its mean by +-exposure_drift, its brightest frame the scene's
  // normal exposure: auto-exposure wanders but keeps the highlights.
  c.brightness = (1.0 + options_.exposure_drift * std::sin(phase)) /
                 (1.0 + options_.exposure_drift);
  const float kelvin = static_cast<float>(options_.white_balance_drift_k *
                                          std::sin(phase / 1.37 + 1.0));
  c.channel_gain = {1.0f + kelvin / 3000.0f, 1.0f, 1.0f - kelvin / 3000.0f};
  c.tag_visible = time_s < options_.tag_gone_after_s;
  return c;
}

FrameConditions BenchConditions::ReadOut(double time_s, double readout_s,
                                         int rotation_deg) const {
  FrameConditions c = At(time_s);
  if (readout_s <= 0.0) return c;
  const bool columns = rotation_deg == 90 || rotation_deg == 270;
  const int lines = columns ? intrinsics_.width_px : intrinsics_.height_px;
  // Upright line i is read k-th.
  const bool reversed = rotation_deg == 90 || rotation_deg == 180;
  std::vector<CameraMotion>& motion = columns ? c.column_motion : c.row_motion;
  for (int i = 0; i < lines; ++i) {
    const int k = reversed ? lines - 1 - i : i;
    const double line_time_s =
        time_s + readout_s * (k - 0.5 * (lines - 1)) / std::max(lines - 1, 1);
    motion.push_back(At(line_time_s).motion);
  }
  return c;
}

}  // namespace softbench
