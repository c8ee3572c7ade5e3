#include "pipelines/measurement/plan_camera.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "calibration/camera_calibration.h"
#include "util/check.h"
#include "util/input_error.h"
#include "util/statistics.h"
#include "vision/frame_source.h"
#include "vision/layout_scale.h"
#include "vision/tag_bitmap.h"
#include "vision/tag_finder.h"

namespace softbench {
namespace {

// The tag's corners over the first frames, combined by a per-coordinate
// median (robust to one bad detection), and each frame's signs of the
// camera's processing into `signs` (if given); throws when the plan's tag
// is absent.
std::array<Eigen::Vector2d, 4> TagCornersFromVideo(
    const TestPlan& plan, VideoReader* reader_ptr, int tag_frames,
    std::vector<TagEdgeSigns>* signs) {
  const TagSpec& tag = *plan.calibration.tag;
  VideoReader& reader = *reader_ptr;
  const std::string& path = reader.path();
  std::vector<std::array<Eigen::Vector2d, 4>> found;
  VideoFrame frame;
  int frames = 0;
  TagFinder finder(
      tag.id, {.detector = {.luma_encoding = reader.info().luma_encoding()}});
  int damaged = 0;
  while (frames < tag_frames && reader.Read(&frame)) {
    ++frames;
    if (frame.damaged) ++damaged;
    if (auto d = finder.Find(frame.luma)) {
      found.push_back(d->corners);
      if (signs != nullptr && d->signs) signs->push_back(*d->signs);
    }
  }
  if (found.empty()) {
    std::string seen = "no tag36h11 tag";
    if (!finder.other_ids().empty()) {
      seen = "tag id(s)";
      for (int id : finder.other_ids()) seen += fmt::format(" {}", id);
    }
    if (damaged > 0) {
      // Damaged frames hide the tag: that is the cause to name.
      throw InputError(fmt::format(
          "{}: {} of the first {} frames are damaged (the decoder reported "
          "errors in the video data), and no tag {} was found in them; "
          "re-copy or re-export the video",
          path, damaged, frames, tag.id));
    }
    throw InputError(fmt::format(
        "{}: found {} in the first {} frames, but the plan's calibration.tag "
        "is id {}; put the tag in view, or set its id (or mm_per_px) in {}",
        path, seen, frames, tag.id, plan.path));
  }
  std::array<Eigen::Vector2d, 4> corners;
  for (int c = 0; c < 4; ++c) {
    for (int axis = 0; axis < 2; ++axis) {
      std::vector<double> values;
      for (const auto& f : found) values.push_back(f[c][axis]);
      corners[c][axis] = Median(values);
    }
  }
  return corners;
}

}  // namespace

CameraIntrinsics PlanIntrinsics(const TestPlan& plan, int width_px,
                                int height_px) {
  const CalibrationSpec& c = plan.calibration;
  if (c.intrinsics_path.empty()) {
    return CameraIntrinsics::FromEquivalentFocalLength(c.focal_length_35mm,
                                                       width_px, height_px);
  }
  const CameraCalibration file = LoadCameraCalibration(c.intrinsics_path);
  if (file.width_px != width_px || file.height_px != height_px) {
    throw InputError(fmt::format(
        "{}: the intrinsics are for {}x{} images but the video is {}x{}; "
        "calibrate at the video's resolution",
        c.intrinsics_path, file.width_px, file.height_px, width_px, height_px));
  }
  CameraIntrinsics k;
  k.width_px = width_px;
  k.height_px = height_px;
  k.fx_px = file.camera_matrix(0, 0);
  k.fy_px = file.camera_matrix(1, 1);
  k.cx_px = file.camera_matrix(0, 2);
  k.cy_px = file.camera_matrix(1, 2);
  k.distortion = file.distortion;
  k.intrinsics_std_px = file.intrinsics_std_px;
  k.distortion_std = file.distortion_std;
  if (auto problem = k.Problem()) {
    throw InputError(c.intrinsics_path + ": " + *problem);
  }
  return k;
}

PlaneMapping PlanMapping(
    const TestPlan& plan, VideoReader* reader,
    const CameraIntrinsics& intrinsics, int tag_frames, std::string* source,
    std::optional<std::array<Eigen::Vector2d, 4>>* tag_corners,
    std::vector<TagEdgeSigns>* tag_signs) {
  const std::string& video_path = reader->path();
  const CalibrationSpec& c = plan.calibration;
  if (c.tag) {
    *source = fmt::format("tag {}", c.tag->id);
    const std::array<Eigen::Vector2d, 4> corners =
        TagCornersFromVideo(plan, reader, tag_frames, tag_signs);
    if (tag_corners != nullptr) *tag_corners = corners;
    PlaneMapping mapping = PlaneMapping::FromTag(
        intrinsics, corners, c.tag->size_mm, c.plane_offset_mm);
    // A plane at or beyond the camera maps pixels to numbers that mean
    // nothing (the homography turns them through infinity).
    const double camera_height_mm = mapping.CameraHeightMm();
    // A camera nearer the tag than its own size would see it fill the
    // frame; one that does not is placed there by a wrong focal length.
    if (!(camera_height_mm > c.tag->size_mm)) {
      throw InputError(fmt::format(
          "{}: {}: with it, the {} mm tag in {} puts the camera {:.3g} mm "
          "from the tag, nearer than the tag is wide; {}",
          plan.path,
          c.intrinsics_path.empty()
              ? fmt::format("calibration.focal_length_35mm {} mm",
                            c.focal_length_35mm)
              : "calibration.intrinsics " + c.intrinsics_path,
          c.tag->size_mm, video_path, camera_height_mm,
          c.intrinsics_path.empty()
              ? "give the camera's 35 mm-equivalent focal length (an "
                "iPhone's main camera: 26 mm)"
              : "calibrate the camera again (softbench calibrate-camera)"));
    }
    if (!(std::abs(c.plane_offset_mm) < camera_height_mm)) {
      throw InputError(fmt::format(
          "{}: calibration.plane_offset_mm: {} mm puts the dots' plane "
          "farther from the tag than the camera, which the tag in {} places "
          "{:.0f} mm above it; give the dots' height above the tag's plane "
          "(negative below it)",
          plan.path, c.plane_offset_mm, video_path, camera_height_mm));
    }
    return mapping;
  }
  const double rotation = c.image_rotation_deg * std::numbers::pi / 180.0;
  if (c.mm_per_px) {
    *source = "mm_per_px";
    return PlaneMapping::FromScale(intrinsics, *c.mm_per_px, rotation);
  }
  if (c.scale_from_dots) {
    VideoFrame frame;
    if (!reader->Read(&frame)) {
      throw InputError(video_path + ": the video has no frames");
    }
    const HeadMarkers head = PlanHeadMarkers(plan).front();
    const LayoutScale scale =
        MeasureLayoutScale(VideoFrameSource(reader, &frame), head, intrinsics);
    if (!scale.found) {
      throw InputError(fmt::format(
          "{}: scale_from_dots: head '{}': {}; or give calibration.tag or "
          "mm_per_px in {}",
          video_path, head.name, scale.why_not, plan.path));
    }
    *source = fmt::format("dots of head '{}'", head.name);
    return PlaneMapping::FromScale(intrinsics, scale.mm_per_px, rotation);
  }
  throw InputError(plan.path +
                   ": calibration needs a tag, mm_per_px or scale_from_dots "
                   "to turn pixels into millimetres");
}

IntrinsicsSensitivity::IntrinsicsSensitivity(
    const TestPlan& plan, const CameraIntrinsics& intrinsics,
    const PlaneMapping& nominal,
    const std::optional<std::array<Eigen::Vector2d, 4>>& tag_corners)
    : nominal_(nominal) {
  const CalibrationSpec& c = plan.calibration;
  const double mm_per_px = nominal.MmPerPixelAt(
      Eigen::Vector2d(intrinsics.width_px / 2.0, intrinsics.height_px / 2.0));
  const auto remap = [&](const CameraIntrinsics& k) {
    return tag_corners ? PlaneMapping::FromTag(k, *tag_corners, c.tag->size_mm,
                                               c.plane_offset_mm)
                       : PlaneMapping::FromScale(
                             k, mm_per_px,
                             c.image_rotation_deg * std::numbers::pi / 180.0);
  };
  // Each parameter a standard error either side (a central difference: a
  // lens's distortion bends far out in the field, where a one-sided step
  // would count its curvature as slope).
  const auto add = [&](double* parameter, double std, CameraIntrinsics* k) {
    if (!(std > 0.0)) return;
    const double value = *parameter;
    *parameter = value + std;
    PlaneMapping plus = remap(*k);
    *parameter = value - std;
    PlaneMapping minus = remap(*k);
    *parameter = value;
    perturbed_.emplace_back(std::move(plus), std::move(minus));
  };
  CameraIntrinsics k = intrinsics;
  double* const focal_and_centre[] = {&k.fx_px, &k.fy_px, &k.cx_px, &k.cy_px};
  for (int i = 0; i < 4; ++i) {
    add(focal_and_centre[i], intrinsics.intrinsics_std_px[i], &k);
  }
  for (size_t i = 0; i < k.distortion.size(); ++i) {
    add(&k.distortion[i], intrinsics.distortion_std[i], &k);
  }
}

Eigen::Vector2d IntrinsicsSensitivity::ChangeUncertaintyMm(
    const Eigen::Vector2d& from_mm, const Eigen::Vector2d& to_mm) const {
  Eigen::Vector2d variance = Eigen::Vector2d::Zero();
  if (!nominal_) return variance;
  // The pixels the nominal mapping took to these points, through each
  // parameter's two mappings instead: the change's derivative in that
  // parameter times its standard error (GUM's linear propagation).
  const Eigen::Vector2d from_px = nominal_->ToPixel(from_mm);
  const Eigen::Vector2d to_px = nominal_->ToPixel(to_mm);
  const auto change = [&](const PlaneMapping& p) {
    return Eigen::Vector2d(p.ToPlane(to_px) - p.ToPlane(from_px));
  };
  for (const auto& [plus, minus] : perturbed_) {
    const Eigen::Vector2d shift = 0.5 * (change(plus) - change(minus));
    variance += shift.array().square().matrix();
  }
  return variance.array().sqrt();
}

std::vector<HeadMarkers> PlanHeadMarkers(const TestPlan& plan) {
  std::vector<HeadMarkers> heads;
  for (const MarkerSpec& m : plan.markers) {
    HeadMarkers h;
    h.name = plan.mechanism.heads[m.head].name;
    h.color_name = m.color;
    h.color = HsvRange::FromBounds(MarkerHsvBounds(m));
    h.dots = m.dots;
    h.dot_diameter_mm = m.dot_diameter_mm;
    h.layout_mm = m.layout_mm;
    heads.push_back(h);
  }
  return heads;
}

TagFittedWhole FitTagWhole(const TestPlan& plan, const cv::Mat& first_luma,
                           const LumaEncoding& encoding,
                           const std::array<Eigen::Vector2d, 4>& tag_corners,
                           const TagModelOptions& options,
                           double max_scale_change) {
  TagFittedWhole whole;
  TagDetectorOptions detector;
  detector.luma_encoding = encoding;
  const std::optional<std::array<Eigen::Vector2d, 4>> midlines =
      RefineTagCorners(first_luma, tag_corners, detector, 0.25);
  if (!midlines) {
    whole.fit.why_not =
        "the border's midlines were not found in the first "
        "frame to start from";
    return whole;
  }
  TagModelOptions fit_options = options;
  fit_options.luma_encoding = encoding;
  whole.fit = FitTagModel(first_luma, Tag36h11Bitmap(plan.calibration.tag->id),
                          *midlines, fit_options);
  if (!whole.fit.found) return whole;
  // The mean length of the sides along each of the tag's axes.
  const auto sides = [](const std::array<Eigen::Vector2d, 4>& c) {
    return Eigen::Vector2d(((c[1] - c[0]).norm() + (c[2] - c[3]).norm()) / 2,
                           ((c[3] - c[0]).norm() + (c[2] - c[1]).norm()) / 2);
  };
  whole.scale = sides(whole.fit.corners).cwiseQuotient(sides(*midlines));
  const double moved = (whole.scale.array() - 1.0).abs().maxCoeff();
  if (!(moved <= max_scale_change)) {
    whole.fit.found = false;
    whole.fit.why_not = fmt::format(
        "the fit moved the scale {:.2f} % from the midlines', more than "
        "they are ever off ({:.2f} %)",
        100.0 * moved, 100.0 * max_scale_change);
    whole.scale = Eigen::Vector2d::Ones();
  }
  return whole;
}

std::array<Eigen::Vector2d, 4> ScaledTagCorners(
    const std::array<Eigen::Vector2d, 4>& corners,
    const Eigen::Vector2d& scale) {
  const std::array<Eigen::Vector2d, 4> square = {
      Eigen::Vector2d(-1, 1), Eigen::Vector2d(1, 1), Eigen::Vector2d(1, -1),
      Eigen::Vector2d(-1, -1)};
  const std::optional<Eigen::Matrix3d> pixel_from_square =
      HomographyThrough(square, corners);
  SOFTBENCH_CHECK(pixel_from_square) << "a tag's corners are a quadrilateral";
  std::array<Eigen::Vector2d, 4> scaled;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d h =
        *pixel_from_square * square[i].cwiseProduct(scale).homogeneous();
    scaled[i] = h.hnormalized();
  }
  return scaled;
}

}  // namespace softbench
