#ifndef SOFTBENCH_VISION_CAMERA_PATH_H_
#define SOFTBENCH_VISION_CAMERA_PATH_H_

#include <optional>
#include <string>
#include <vector>

#include "vision/camera.h"
#include "vision/camera_motion.h"

namespace softbench {

struct CameraPathOptions {
  // A step (a knock) is a change of the camera's shift larger than this
  // between the medians of the step_frames before and after it [px].
  double step_px = 0.3;
  int step_frames = 8;
  // Frames on each side of a step taken as registered (the camera moves).
  int transition_frames = 3;
  // Half width of the running line fit between steps [s]: longer than a
  // video codec's key-frame interval, whose re-encoding moves still edges by
  // a few thousandths of a pixel for seconds at a time; far shorter than a
  // tripod's drift changes its pace.
  double half_window_s = 2.5;

  std::optional<std::string> Check() const;
};

// The camera's path through a video from each frame's own registration:
// smooth between knocks, a step at each. Each frame's motion becomes a
// straight line's (in time) through its stretch's frames (between steps)
// within half_window_s; at a knock, the frames' own. Tremor (hundredths to
// tenths of a pixel, several hertz) is left to the windows' medians, where it
// averages out; what must be removed, drift and knocks, is kept. `valid[i]`
// false: frame i was not registered (its entry is returned as given). A gap in
// `times_s` longer than `max_gap_s` (a seek between windows) starts a new
// stretch.
std::vector<CameraMotion> SmoothCameraPath(
    const CameraIntrinsics& intrinsics, const std::vector<double>& times_s,
    const std::vector<CameraMotion>& raw, const std::vector<bool>& valid,
    double max_gap_s, const CameraPathOptions& options = {});

}  // namespace softbench

#endif  // SOFTBENCH_VISION_CAMERA_PATH_H_
