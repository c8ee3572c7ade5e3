#include "pipelines/video_measurement.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "calibration/camera_calibration.h"
#include "util/input_error.h"
#include "util/progress.h"
#include "util/statistics.h"
#include "vision/frame_source.h"
#include "vision/layout_scale.h"
#include "vision/tag_detector.h"
#include "vision/video_reader.h"

namespace softbench {

std::optional<std::string> VideoMeasurementOptions::Check() const {
  if (tag_frames < 1) return "tag_frames must be >= 1";
  if (!(rest_s > 0.0)) return "rest_s must be > 0";
  return tracker.Check();
}

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// The tag's corners over the first frames, combined by a per-coordinate
// median (robust to one bad detection); throws when the plan's tag is absent.
PlaneMapping MappingFromTag(const TestPlan& plan, const std::string& path,
                            const CameraIntrinsics& intrinsics,
                            int tag_frames) {
  const TagSpec& tag = *plan.calibration.tag;
  VideoReaderOptions reader_options;
  reader_options.want_bgr = false;
  VideoReader reader(path, reader_options);
  std::vector<std::array<Eigen::Vector2d, 4>> found;
  std::set<int> other_ids;
  VideoFrame frame;
  int frames = 0;
  while (frames < tag_frames && reader.Read(&frame)) {
    ++frames;
    for (const TagDetection& d : DetectTags(frame.luma)) {
      if (d.id == tag.id) {
        found.push_back(d.corners);
      } else {
        other_ids.insert(d.id);
      }
    }
  }
  if (found.empty()) {
    std::string seen = "no tag36h11 tag";
    if (!other_ids.empty()) {
      seen = "tag id(s)";
      for (int id : other_ids) seen += fmt::format(" {}", id);
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
  return PlaneMapping::FromTag(intrinsics, corners, tag.size_mm,
                               plan.calibration.plane_offset_mm);
}

double MeanPairDistance(const std::vector<Eigen::Vector2d>& points) {
  const std::vector<double> d = PairDistances(points);
  double sum = 0.0;
  for (double v : d) sum += v;
  return d.empty() ? 0.0 : sum / d.size();
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
  if (auto problem = k.Check()) {
    throw InputError(c.intrinsics_path + ": " + *problem);
  }
  return k;
}

PlaneMapping PlanMapping(const TestPlan& plan, const std::string& video_path,
                         const CameraIntrinsics& intrinsics, int tag_frames,
                         std::string* source) {
  const CalibrationSpec& c = plan.calibration;
  if (c.tag) {
    *source = fmt::format("tag {}", c.tag->id);
    return MappingFromTag(plan, video_path, intrinsics, tag_frames);
  }
  const double rotation = c.image_rotation_deg * std::numbers::pi / 180.0;
  if (c.mm_per_px) {
    *source = "mm_per_px";
    return PlaneMapping::FromScale(intrinsics, *c.mm_per_px, rotation);
  }
  if (c.scale_from_dots) {
    VideoReaderOptions reader_options;
    reader_options.want_bgr = false;
    VideoReader reader(video_path, reader_options);
    VideoFrame frame;
    if (!reader.Read(&frame)) {
      throw InputError(video_path + ": the video has no frames");
    }
    const HeadMarkers head = PlanHeadMarkers(plan).front();
    const LayoutScale scale =
        MeasureLayoutScale(VideoFrameSource(&reader, &frame), head, intrinsics);
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

std::vector<HeadMarkers> PlanHeadMarkers(const TestPlan& plan) {
  std::vector<HeadMarkers> heads;
  for (const MarkerSpec& m : plan.markers) {
    HeadMarkers h;
    h.name = plan.mechanism.heads[m.head].name;
    h.color_name = m.color;
    if (m.hsv) {
      h.color = HsvRange::FromBounds(*m.hsv);
    } else {
      h.color = *BuiltinHsvRange(m.color);
    }
    h.dots = m.dots;
    h.dot_diameter_mm = m.dot_diameter_mm;
    h.layout_mm = m.layout_mm;
    heads.push_back(h);
  }
  return heads;
}

VideoMeasurement MeasureVideo(const TestPlan& plan,
                              const std::string& video_path,
                              const VideoMeasurementOptions& options) {
  if (auto problem = options.Check()) {
    throw std::invalid_argument("MeasureVideo: " + *problem);
  }
  VideoReaderOptions reader_options;
  reader_options.want_bgr = false;
  VideoReader reader(video_path, reader_options);
  const VideoInfo& info = reader.info();
  const CameraIntrinsics intrinsics =
      PlanIntrinsics(plan, info.width_px, info.height_px);
  VideoMeasurement m;
  m.video_path = video_path;
  const CalibrationSpec& c = plan.calibration;
  const PlaneMapping mapping = PlanMapping(plan, video_path, intrinsics,
                                           options.tag_frames, &m.scale_source);
  m.mm_per_px = mapping.MmPerPixelAt(
      Eigen::Vector2d(intrinsics.width_px / 2.0, intrinsics.height_px / 2.0));
  HeadTracker tracker(mapping, PlanHeadMarkers(plan), options.tracker);

  ProgressBar progress("measure", info.frame_count, options.progress);
  VideoFrame frame;
  while (reader.Read(&frame)) {
    const VideoFrameSource source(&reader, &frame);
    FrameSample sample;
    sample.frame = frame.index;
    sample.time_s = frame.time_s;
    bool full = false;
    for (HeadObservation& obs : tracker.Measure(source)) {
      if (m.frames.empty() && !obs.complete) {
        throw InputError(fmt::format(
            "{}: first frame: {}", video_path,
            obs.note.empty() ? "not every dot was found" : obs.note));
      }
      m.missing_dots += static_cast<int>(obs.dots.size()) - obs.dots_found;
      m.rejected_blobs += obs.rejected_blobs;
      full = full || obs.full_frame;
      sample.heads.push_back({std::move(obs), {}, {}});
    }
    m.full_frame_frames += full;
    m.frames.push_back(std::move(sample));
    progress.Update(static_cast<int64_t>(m.frames.size()));
  }
  progress.Finish();
  if (m.frames.empty())
    throw InputError(video_path + ": the video has no frames");

  // Rest: before the first actuation when the plan has times.
  double rest_end = options.rest_s;
  if (plan.HasTimes()) {
    rest_end = *plan.tests.front().actuate_s;
    for (const PlanTest& t : plan.tests)
      rest_end = std::min(rest_end, *t.actuate_s);
  }
  for (size_t h = 0; h < plan.markers.size(); ++h) {
    std::vector<double> ys, zs;
    for (const FrameSample& f : m.frames) {
      const HeadObservation& obs = f.heads[h].observation;
      if (f.time_s < rest_end && obs.complete) {
        ys.push_back(obs.position_mm.x());
        zs.push_back(obs.position_mm.y());
      }
    }
    if (ys.empty()) {
      throw InputError(fmt::format(
          "{}: head '{}' was not seen whole before t = {:.3f} s, so it has "
          "no rest position; start the video at rest",
          video_path, plan.mechanism.heads[plan.markers[h].head].name,
          rest_end));
    }
    m.rest_mm.emplace_back(Median(ys), Median(zs));
  }
  for (FrameSample& f : m.frames) {
    for (size_t h = 0; h < f.heads.size(); ++h) {
      HeadSample& s = f.heads[h];
      s.displacement_mm = s.observation.position_mm - m.rest_mm[h];
      s.binary_displacement_mm =
          s.observation.binary_position_mm - m.rest_mm[h];
    }
  }
  if (c.intrinsics_path.empty()) {
    m.distortion = CheckDistortion(plan, m.frames, m.scale_source);
  }
  return m;
}

DistortionCheck CheckDistortion(const TestPlan& plan,
                                const std::vector<FrameSample>& frames,
                                const std::string& scale_source) {
  DistortionCheck check;
  check.tolerance = plan.calibration.distortion_tolerance;
  std::vector<double> ratios;
  for (const FrameSample& f : frames) {
    for (size_t h = 0; h < f.heads.size(); ++h) {
      const HeadObservation& obs = f.heads[h].observation;
      const double nominal = MeanPairDistance(plan.markers[h].layout_mm);
      if (!obs.complete || nominal <= 0.0) continue;
      std::vector<Eigen::Vector2d> dots;
      for (const DotObservation& d : obs.dots) dots.push_back(d.plane_mm);
      ratios.push_back(MeanPairDistance(dots) / nominal);
    }
  }
  if (ratios.empty()) return check;
  check.performed = true;
  check.median_ratio = Median(ratios);
  // The 5th..95th percentiles: frames in mid-motion (blur) are not the lens.
  check.min_ratio = Quantile(ratios, 0.05);
  check.max_ratio = Quantile(ratios, 0.95);
  const double offset = std::abs(check.median_ratio - 1.0);
  const double spread = check.max_ratio - check.min_ratio;
  check.warn = offset > check.tolerance || spread > check.tolerance;
  check.message = fmt::format(
      "dot spacing measured through the {} scale is {:+.3f} % of the plan's "
      "layout (5-95 % range {:.3f} % over the video; tolerance {:.3f} %)",
      scale_source, 100.0 * (check.median_ratio - 1.0), 100.0 * spread,
      100.0 * check.tolerance);
  if (check.warn) {
    check.message +=
        "; the scale differs across the field: calibrate the lens "
        "(softbench calibrate-camera) and set calibration.intrinsics, or "
        "check layout_mm against the printed dots";
  }
  return check;
}

std::string TrajectoryCsv(const TestPlan& plan,
                          const VideoMeasurement& measurement) {
  std::string csv =
      "frame,time_s,head,u_px,v_px,y_mm,z_mm,sigma_mm,dots_found,dots,"
      "rotation_rad,binary_y_mm,binary_z_mm,full_frame,note\n";
  for (const FrameSample& f : measurement.frames) {
    for (size_t h = 0; h < f.heads.size(); ++h) {
      const HeadSample& s = f.heads[h];
      const HeadObservation& o = s.observation;
      std::string note = o.note;
      std::replace(note.begin(), note.end(), ',', ';');
      csv += fmt::format(
          "{},{:.6f},{},{:.4f},{:.4f},{:.5f},{:.5f},{:.5f},{},{},{:.6f},"
          "{:.5f},{:.5f},{},{}\n",
          f.frame, f.time_s, plan.mechanism.heads[plan.markers[h].head].name,
          o.pixel.x(), o.pixel.y(), s.displacement_mm.x(),
          s.displacement_mm.y(), o.sigma_mm, o.dots_found, o.dots.size(),
          o.rotation_rad, s.binary_displacement_mm.x(),
          s.binary_displacement_mm.y(), o.full_frame ? 1 : 0, note);
    }
  }
  return csv;
}

}  // namespace softbench
