#ifndef SOFTBENCH_PIPELINES_SYNTHETIC_BENCH_CONDITIONS_H_
#define SOFTBENCH_PIPELINES_SYNTHETIC_BENCH_CONDITIONS_H_

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vision/camera.h"
#include "vision/camera_motion.h"

namespace softbench {

// A knock on the tripod: the image steps to a new rest position.
struct CameraBump {
  double time_s = 0.0;
  Eigen::Vector2d shift_px = Eigen::Vector2d::Zero();  // at the principal point
  double roll_deg = 0.0;                               // clockwise on screen
};

// What a phone on a tripod does while it films, for the renderer: the camera
// moves (drift, tremor, bumps) and auto-exposure and white balance wander.
// Shifts are of the image content at the principal point [px].
struct BenchConditionsOptions {
  // Reached linearly over the whole video (a ball head creeping).
  Eigen::Vector2d drift_px = Eigen::Vector2d::Zero();
  // RMS of a band-limited tremble (a sum of 2-12 Hz sinusoids per axis with
  // seeded phases; a floor's and a hand's vibration).
  double tremor_px = 0.0;
  // Each settles on its new position within about 0.1 s (a damped step).
  std::vector<CameraBump> bumps;
  // Relative amplitude of the brightness's slow wander about its mean (0.3:
  // +-30 %), a sinusoid of period drift_period_s whose brightest frame is
  // the scene's normal exposure (auto-exposure keeps the highlights).
  double exposure_drift = 0.0;
  // Amplitude of the white balance's wander [K]: +dT scales blue by
  // (1 + dT / 3000) and red by (1 - dT / 3000), roughly a camera's change
  // per few hundred kelvin near daylight; period 1.37 x drift_period_s.
  double white_balance_drift_k = 0.0;
  double drift_period_s = 20.0;
  // From this time on the tag is taken away (a hand, a cable over it).
  double tag_gone_after_s = INFINITY;
  uint64_t seed = 1;

  std::optional<std::string> Problem() const;
};

// The conditions of one frame.
struct FrameConditions {
  CameraMotion motion;  // since the video's start
  // A rolling shutter: the camera's motion when each line of the upright
  // frame was read, by row, or by column for a sensor turned a quarter
  // (a portrait video); both empty: every line read at once (`motion`).
  std::vector<CameraMotion> row_motion;
  std::vector<CameraMotion> column_motion;
  double brightness = 1.0;             // multiplies the exposure
  cv::Vec3f channel_gain = {1, 1, 1};  // BGR, white balance
  bool tag_visible = true;
};

class BenchConditions {
 public:
  BenchConditions(const BenchConditionsOptions& options,
                  const CameraIntrinsics& intrinsics, double duration_s);
  FrameConditions At(double time_s) const;
  // The conditions of a frame read by a rolling shutter: At(time_s), with
  // the camera's motion when each line was read, over `readout_s` from the
  // first line to the last, `time_s` the middle line's time. Lines are the
  // stored video's rows, top first: the upright frame's columns from the
  // right for a `rotation_deg` of 90, from the left for 270, its rows from
  // the bottom for 180. `readout_s` 0: At(time_s).
  FrameConditions ReadOut(double time_s, double readout_s,
                          int rotation_deg) const;

 private:
  BenchConditionsOptions options_;
  CameraIntrinsics intrinsics_;
  double duration_s_;
  // Tremor: per axis, frequencies [Hz], phases [rad] and a common amplitude.
  std::vector<double> frequencies_hz_;
  std::vector<Eigen::Vector2d> phases_;
  double tremor_amplitude_px_ = 0.0;
};

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_SYNTHETIC_BENCH_CONDITIONS_H_
