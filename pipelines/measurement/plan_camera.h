#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_PLAN_CAMERA_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_PLAN_CAMERA_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "vision/camera.h"
#include "vision/head_tracker.h"
#include "vision/plane_mapping.h"
#include "vision/tag_detector.h"
#include "vision/tag_model.h"
#include "vision/video_reader.h"

namespace softbench {

// The camera intrinsics the plan implies for a video of the given size: its
// intrinsics file (checked against the size) or its focal length.
CameraIntrinsics PlanIntrinsics(const TestPlan& plan, int width_px,
                                int height_px);

// Pixels to the dot plane as the plan's calibration says: from its tag
// (median of the corners over the video's first `tag_frames` frames), its
// mm_per_px or the first head's dots. Reads on from the reader's position
// (the video's start). `source` receives a name for it ("tag 0",
// "mm_per_px"); `tag_corners` (optional) the tag's corners the mapping was
// made from, `tag_signs` (optional) what the tag's border showed of the
// camera's processing in each frame that gave it. Throws InputError when
// the plan's scale is not in the video.
PlaneMapping PlanMapping(
    const TestPlan& plan, VideoReader* reader,
    const CameraIntrinsics& intrinsics, int tag_frames, std::string* source,
    std::optional<std::array<Eigen::Vector2d, 4>>* tag_corners = nullptr,
    std::vector<TagEdgeSigns>* tag_signs = nullptr);

// The plan's tag fitted whole (vision/tag_model.h) in the first frame,
// from the corners its mapping was made from: the fit, and its size over
// the border's midlines' in the same frame (RefineTagCorners) along the
// tag's two axes. The processing moves the midlines' scale, not their
// perspective, which one frame's fit knows less well than the midlines
// averaged over the video: so the scale is what is taken from the fit
// (ScaledTagCorners). Not found (fit.why_not) where the midlines cannot be
// refined in the frame, or the fit moves their scale along either axis by
// more than `max_scale_change` (a fraction): the midlines were measured
// off by at most 0.51 % on small cells (docs/measurement.md), so a fit
// that moves them twice that far has fitted something other than the tag
// (a shadow, a finger, a fold).
struct TagFittedWhole {
  TagModelFit fit;
  Eigen::Vector2d scale = Eigen::Vector2d::Ones();  // along x, y
  // The mean size over the midlines', - 1.
  double ScaleChange() const { return scale.mean() - 1.0; }
};
TagFittedWhole FitTagWhole(const TestPlan& plan, const cv::Mat& first_luma,
                           const LumaEncoding& encoding,
                           const std::array<Eigen::Vector2d, 4>& tag_corners,
                           const TagModelOptions& options,
                           double max_scale_change = 0.01);

// A tag's corners (libapriltag's order) scaled about its centre along its
// own two axes, through the plane's homography they make.
std::array<Eigen::Vector2d, 4> ScaledTagCorners(
    const std::array<Eigen::Vector2d, 4>& corners,
    const Eigen::Vector2d& scale);

// How the plan's mapping depends on the intrinsics' standard errors
// (CameraIntrinsics::intrinsics_std_px, distortion_std): the mapping made
// again from the same evidence (the tag's corners, or the scale) with each
// parameter moved by its standard error either way, one at a time. A
// calibration's fit gives only each parameter's standard deviation, not their
// covariance, so the parameters' effects add in quadrature.
class IntrinsicsSensitivity {
 public:
  IntrinsicsSensitivity() = default;
  // `nominal` is the plan's mapping through `intrinsics`; `tag_corners` the
  // corners it was made from, when the plan has a tag (else the mapping is
  // a scale's, made again with the same scale at the image centre, which
  // for a scale from the dots overstates the term: the dots would have
  // taken part of the change into the scale).
  IntrinsicsSensitivity(
      const TestPlan& plan, const CameraIntrinsics& intrinsics,
      const PlaneMapping& nominal,
      const std::optional<std::array<Eigen::Vector2d, 4>>& tag_corners);

  // False without standard errors: no term.
  bool Known() const { return !perturbed_.empty(); }
  // The standard uncertainty per axis [mm] that the intrinsics give the
  // change of a point on the dot plane from `from_mm` to `to_mm` (plane
  // coordinates, as the mapping gives them): each parameter's change of
  // the change, in quadrature.
  Eigen::Vector2d ChangeUncertaintyMm(const Eigen::Vector2d& from_mm,
                                      const Eigen::Vector2d& to_mm) const;

 private:
  std::optional<PlaneMapping> nominal_;
  // Per parameter with an error, the mapping with it a standard error
  // above and below its value.
  std::vector<std::pair<PlaneMapping, PlaneMapping>> perturbed_;
};

// The plan's heads as the tracker needs them.
std::vector<HeadMarkers> PlanHeadMarkers(const TestPlan& plan);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_PLAN_CAMERA_H_
