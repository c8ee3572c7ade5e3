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
  // Half width of the running line fit between steps [s]: several of a
  // video codec's key-frame intervals, as its re-encoding moves still edges
  // by hundredths of a pixel for a second or two at a time (a window of
  // ±2.5 s left a still 1080p clip at CRF 17 with 0.0045 mm of error, ±10 s
  // with 0.0031 mm); far shorter than a tripod's drift changes its pace.
  double half_window_s = 10.0;
  // Tremor [px] above which every frame keeps its own registration:
  // the robust scatter of the shift from one frame to the next (1.4826
  // times the median absolute deviation of the differences, over sqrt 2).
  // A still camera's registration scatters by under 0.003 px from frame to
  // frame, a phone on a tripod by 0.03-0.08 px; tremor of 0.01 px left to a
  // 30-frame window's median costs it 0.002 px.
  double tremor_px = 0.01;

  std::optional<std::string> Problem() const;
};

// The camera's path through a video from each frame's own registration.
// A camera that trembles (tremor_px) keeps each frame's own motion: tremor is
// real motion of the image, 0.08 px RMS on a phone's tripod, and left to the
// windows' medians it would cost a 30-frame window 0.003 mm. A still camera's
// registration wobbles instead with the codec's re-encoding of still edges,
// so its path is taken as smooth between knocks: each frame's motion becomes
// a straight line's (in time) through its segment's frames (between steps)
// within half_window_s, and at a knock the frames keep their own. Drift and
// knocks are kept either way. `valid[i]` false: frame i was not registered
// (its entry is returned as given). A gap in `times_s` longer than
// `max_gap_s` (a seek between windows, frames not registered) is a step
// when the frames either side disagree by more than step_px (a knock while
// it was not filmed); else the line runs across it, so reading only the
// windows averages the codec's wobble over as many seconds as reading all.
std::vector<CameraMotion> SmoothCameraPath(
    const CameraIntrinsics& intrinsics, const std::vector<double>& times_s,
    const std::vector<CameraMotion>& raw, const std::vector<bool>& valid,
    double max_gap_s, const CameraPathOptions& options = {});

}  // namespace softbench

#endif  // SOFTBENCH_VISION_CAMERA_PATH_H_
