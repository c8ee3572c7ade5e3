#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_FRAME_SAMPLE_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_FRAME_SAMPLE_H_

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "vision/camera_motion.h"
#include "vision/head_tracker.h"
#include "vision/rolling_shutter.h"

namespace softbench {

// One head in one frame.
struct HeadSample {
  HeadObservation observation;
  // Displacement from the head's rest position [mm] (NaN when no dot was
  // found), from the luma-refined centres and from the thesis's binary ones.
  Eigen::Vector2d displacement_mm;
  Eigen::Vector2d binary_displacement_mm;
  // The head's pose out of the plane against its rest (issue 27): its lift
  // toward the camera [mm], its tilt about world y and z [rad], and the
  // parallax they add to the dots' apparent centre [mm], which
  // displacement_mm has taken out when the measurement corrects lift
  // (binary_displacement_mm, the thesis's method, never). NaN when the
  // head was not complete or its pose not found.
  double lift_mm = NAN;
  Eigen::Vector2d tilt_rad = Eigen::Vector2d::Constant(NAN);
  Eigen::Vector2d parallax_mm = Eigen::Vector2d::Constant(NAN);
};

struct FrameSample {
  int64_t frame = 0;
  double time_s = 0.0;
  std::vector<HeadSample> heads;  // in the plan's head order
  // The frame's registration to the bench: false when the tag could not be
  // located (the heads are then not measured in this frame: never against a
  // stale registration). The camera's shift since the reference frames is
  // that of the content at the principal point [px]; roll clockwise [rad].
  bool registered = true;
  // The decoder reported errors in this frame (damaged video data): its
  // heads are not measured.
  bool damaged = false;
  // The frame was coded as an I picture (VideoFrame::intra).
  bool intra = false;
  CameraMotion camera_motion;  // the camera's path (SmoothCameraPath)
  Eigen::Vector2d camera_shift_px = Eigen::Vector2d::Zero();
  double camera_roll_rad = 0.0;
  // The tag's corners in this frame, where registration located them.
  std::optional<std::array<Eigen::Vector2d, 4>> tag_corners;
  // The registration's misfits against a rolling shutter's shear.
  ShutterShearSums shear_sums;
};

// The heads of one frame, cut out for the report's annotated pictures.
struct HeadCrop {
  cv::Mat bgr;                // CV_8UC3
  Eigen::Vector2d origin_px;  // the crop's top-left corner in the frame
};

struct FrameSnapshot {
  double requested_s = 0.0;  // the time asked for
  int64_t frame = 0;
  double time_s = 0.0;
  std::vector<HeadCrop> heads;  // in the plan's head order
};

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_FRAME_SAMPLE_H_
