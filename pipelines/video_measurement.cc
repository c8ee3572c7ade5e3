#include "pipelines/video_measurement.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <set>
#include <thread>

#include "calibration/camera_calibration.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
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
  if (auto problem = registration.Check()) return problem;
  if (auto problem = camera_path.Check()) return problem;
  return tracker.Check();
}

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// The tag's corners over the first frames, combined by a per-coordinate
// median (robust to one bad detection); throws when the plan's tag is absent.
std::array<Eigen::Vector2d, 4> TagCornersFromVideo(const TestPlan& plan,
                                                   const std::string& path,
                                                   int tag_frames) {
  const TagSpec& tag = *plan.calibration.tag;
  VideoReaderOptions reader_options;
  reader_options.want_bgr = false;
  VideoReader reader(path, reader_options);
  std::vector<std::array<Eigen::Vector2d, 4>> found;
  std::set<int> other_ids;
  VideoFrame frame;
  int frames = 0;
  const TagDetector detector;
  // The tag stays put: after the first frame that shows it, only the region
  // around it (grown by half its size) is searched, ten times faster.
  cv::Rect region;
  while (frames < tag_frames && reader.Read(&frame)) {
    ++frames;
    const cv::Mat luma = region.empty() ? frame.luma : frame.luma(region);
    for (TagDetection d : detector.Detect(luma)) {
      for (Eigen::Vector2d& corner : d.corners) {
        corner += Eigen::Vector2d(region.x, region.y);
      }
      if (d.id == tag.id) {
        found.push_back(d.corners);
        if (region.empty()) {
          const double side_px =
              (d.corners[0] - d.corners[2]).norm() / std::numbers::sqrt2;
          region = BoxAround({d.corners.begin(), d.corners.end()},
                             0.5 * side_px, frame.luma.size());
        }
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
  return corners;
}

// A head observation for a frame that could not be measured at all.
HeadObservation Unmeasured(int dots, const std::string& why) {
  HeadObservation obs;
  obs.dots.assign(dots, DotObservation{});
  obs.position_mm = obs.pixel = obs.binary_position_mm =
      Eigen::Vector2d(kNan, kNan);
  obs.note = why;
  return obs;
}

double MeanPairDistance(const std::vector<Eigen::Vector2d>& points) {
  const std::vector<double> d = PairDistances(points);
  double sum = 0.0;
  for (double v : d) sum += v;
  return d.empty() ? 0.0 : sum / d.size();
}

// Sorted spans, overlapping (or touching) ones merged, those starting
// beyond the video's last frame dropped.
std::vector<TimeSpan> MergeSpans(std::vector<TimeSpan> spans, double duration_s,
                                 double half_frame_s) {
  std::sort(spans.begin(), spans.end(),
            [](const TimeSpan& a, const TimeSpan& b) {
              return a.start_s < b.start_s;
            });
  std::vector<TimeSpan> merged;
  for (TimeSpan span : spans) {
    span.start_s = std::max(span.start_s, 0.0);
    if (span.start_s >= span.end_s ||
        span.start_s > duration_s - half_frame_s) {
      continue;
    }
    if (!merged.empty() && span.start_s <= merged.back().end_s + half_frame_s) {
      merged.back().end_s = std::max(merged.back().end_s, span.end_s);
    } else {
      merged.push_back(span);
    }
  }
  return merged;
}

// What every frame is registered to: the video's first frame, its tag (the
// corners of the mapping, re-located in that frame) and where its static
// patches may be taken.
struct RegistrationReference {
  cv::Mat luma;
  cv::Mat static_mask;
  std::optional<TagReference> tag;
};

// Outside the mechanism: the hull of its fixed anchors and heads at rest,
// grown by 14 mm (the bellows' 11 mm half width where they meet the
// anchors, and the heads' travel), is where things move; the ring and the
// mounts outside it stay. The mapping's origin is its tag's (or
// the image centre's), not the mechanism's: the heads found in `first`
// place the mechanism's frame on the plane (the axes are the same).
cv::Mat StaticMask(const TestPlan& plan, const PlaneMapping& mapping,
                   const FrameSource& first) {
  HeadTracker tracker(mapping, PlanHeadMarkers(plan));
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
  int heads = 0;
  const std::vector<HeadObservation> found = tracker.Measure(first);
  for (size_t h = 0; h < found.size(); ++h) {
    if (!found[h].position_mm.allFinite()) continue;
    offset += found[h].position_mm -
              plan.mechanism.heads[plan.markers[h].head].rest_mm;
    ++heads;
  }
  const cv::Size size = first.luma().size();
  // Without a head in view the first frame fails later with its own
  // message; no patch is taken meanwhile.
  if (heads == 0) return cv::Mat(size, CV_8UC1, cv::Scalar(0));
  offset /= heads;
  std::vector<cv::Point> outline;
  const auto add = [&](const Eigen::Vector2d& mm) {
    const Eigen::Vector2d px = mapping.ToPixel(mm + offset);
    outline.emplace_back(cvRound(px.x()), cvRound(px.y()));
  };
  for (const FixedAnchor& a : plan.mechanism.fixed_anchors) add(a.position_mm);
  for (const Head& h : plan.mechanism.heads) add(h.rest_mm);
  std::vector<cv::Point> hull;
  cv::convexHull(outline, hull);
  // Grown by 14 mm: a convex polygon grown by a disc is the hull of discs
  // at its corners (a dilation of the image with a 60 px disc cost more than
  // measuring 50 frames).
  const Eigen::Vector2d centre(size.width / 2.0, size.height / 2.0);
  const double grow = 14.0 / mapping.MmPerPixelAt(centre);
  std::vector<cv::Point> grown;
  for (const cv::Point& corner : hull) {
    for (int k = 0; k < 64; ++k) {
      const double angle = 2.0 * M_PI * k / 64;
      grown.emplace_back(cvRound(corner.x + grow * std::cos(angle)),
                         cvRound(corner.y + grow * std::sin(angle)));
    }
  }
  cv::convexHull(grown, hull);
  cv::Mat moving(size, CV_8UC1, cv::Scalar(0));
  cv::fillConvexPoly(moving, hull, cv::Scalar(255));
  return 255 - moving;
}

RegistrationReference MakeRegistrationReference(
    const TestPlan& plan, const std::string& path, const PlaneMapping& mapping,
    const std::optional<std::array<Eigen::Vector2d, 4>>& tag_corners) {
  VideoReaderOptions reader_options;
  reader_options.want_bgr = false;
  VideoReader reader(path, reader_options);
  VideoFrame frame;
  if (!reader.Read(&frame))
    throw InputError(path + ": the video has no frames");
  RegistrationReference reference;
  reference.luma = frame.luma.clone();
  reference.static_mask =
      StaticMask(plan, mapping, VideoFrameSource(&reader, &frame));
  if (tag_corners) {
    TagReference& tag = reference.tag.emplace();
    tag.id = plan.calibration.tag->id;
    tag.corners = RefineTagCorners(reference.luma, *tag_corners, {}, 0.25)
                      .value_or(*tag_corners);
  }
  return reference;
}

// Measures spans of a video with one reader and one tracker, keeping the
// frames, the snapshots asked for and the counts.
// A time a snapshot was asked for, and the time of its nearest frame.
struct SnapshotTime {
  double requested_s, frame_s;
};

class SpanMeasurer {
 public:
  // `registration`, when given, registers every frame to the bench before
  // its heads are measured, through `mapping` after the camera's motion.
  SpanMeasurer(const TestPlan& plan, const std::string& path,
               const PlaneMapping& mapping, double mm_per_px,
               HeadTracker tracker,
               std::unique_ptr<BenchRegistration> registration,
               const std::vector<SnapshotTime>& snapshot_times,
               int decoder_threads, std::atomic<int64_t>* frames_done)
      : plan_(&plan),
        mapping_(mapping),
        registration_(std::move(registration)),
        mm_per_px_(mm_per_px),
        reader_(std::make_unique<VideoReader>(
            path, VideoReaderOptions{.want_luma = true,
                                     .want_bgr = false,
                                     .threads = decoder_threads})),
        tracker_(std::move(tracker)),
        snapshot_times_(&snapshot_times),
        frames_done_(frames_done) {}

  const HeadTracker& tracker() const { return tracker_; }
  int patch_count() const {
    return registration_ ? registration_->patch_count() : 0;
  }
  // Throw InputError when the first frame measured lacks a dot: it is the
  // heads' reference.
  void RequireCompleteFirstFrame() { first_frame_complete_ = true; }

  // The frames of `span`: after a seek to its start, or read on from the
  // reader's position; `poll` is called after each frame.
  void Measure(const TimeSpan& span, bool seek,
               const std::function<void()>& poll) {
    VideoFrame frame;
    if (seek) {
      frame = reader_->SeekTo(span.start_s);
      tracker_.ForgetPositions();
    } else if (!reader_->Read(&frame)) {
      return;
    }
    // Snapshots are kept at their nearest frames' exact times.
    constexpr double kSameFrameS = 1e-6;
    auto next_snapshot = std::lower_bound(
        snapshot_times_->begin(), snapshot_times_->end(),
        frame.time_s - kSameFrameS,
        [](const SnapshotTime& s, double t) { return s.frame_s < t; });
    do {
      if (frame.time_s >= span.end_s) break;
      const VideoFrameSource source(reader_.get(), &frame);
      FrameSample sample;
      sample.frame = frame.index;
      sample.time_s = frame.time_s;
      if (!Register(frame, &sample)) {
        frames_.push_back(std::move(sample));
        ++*frames_done_;
        poll();
        continue;
      }
      bool full = false;
      for (HeadObservation& obs : tracker_.Measure(source)) {
        if (first_frame_complete_ && frames_.empty() && !obs.complete) {
          throw InputError(fmt::format(
              "{}: first frame measured (t = {:.3f} s): {}", reader_->path(),
              frame.time_s,
              obs.note.empty() ? "not every dot was found" : obs.note));
        }
        missing_dots_ += static_cast<int>(obs.dots.size()) - obs.dots_found;
        rejected_blobs_ += obs.rejected_blobs;
        full = full || obs.full_frame;
        sample.heads.push_back({std::move(obs), {}, {}});
      }
      full_frame_frames_ += full;
      for (; next_snapshot != snapshot_times_->end() &&
             frame.time_s >= next_snapshot->frame_s - kSameFrameS;
           ++next_snapshot) {
        if (frame.time_s <= next_snapshot->frame_s + kSameFrameS) {
          snapshots_.push_back(SnapshotHeads(source, sample, *plan_, mm_per_px_,
                                             next_snapshot->requested_s));
        }
      }
      frames_.push_back(std::move(sample));
      ++*frames_done_;
      poll();
    } while (reader_->Read(&frame));
  }

  // Appends what was measured (later spans than `m` holds) to `m`.
  void MoveInto(VideoMeasurement* m) {
    std::move(frames_.begin(), frames_.end(), std::back_inserter(m->frames));
    std::move(snapshots_.begin(), snapshots_.end(),
              std::back_inserter(m->snapshots));
    m->missing_dots += missing_dots_;
    m->rejected_blobs += rejected_blobs_;
    m->full_frame_frames += full_frame_frames_;
    m->unregistered_frames += unregistered_frames_;
    if (m->unregistered_reason.empty()) {
      m->unregistered_reason = unregistered_reason_;
    }
  }

 private:
  // Registers the frame to the bench and gives the tracker the frame's
  // mapping; false (the sample filled with unmeasured heads) when the frame
  // cannot be registered.
  bool Register(const VideoFrame& frame, FrameSample* sample) {
    if (registration_ == nullptr) return true;
    const FrameRegistration r = registration_->Register(frame.luma);
    sample->registered = r.registered;
    if (!r.registered) {
      if (first_frame_complete_ && frames_.empty()) {
        throw InputError(fmt::format(
            "{}: first frame measured (t = {:.3f} s) cannot be registered to "
            "the bench: {}",
            reader_->path(), frame.time_s, r.why_not));
      }
      ++unregistered_frames_;
      if (unregistered_reason_.empty()) unregistered_reason_ = r.why_not;
      for (const MarkerSpec& marker : plan_->markers) {
        sample->heads.push_back(
            {Unmeasured(marker.dots, "frame not registered: " + r.why_not),
             Eigen::Vector2d(kNan, kNan), Eigen::Vector2d(kNan, kNan)});
      }
      return false;
    }
    sample->camera_motion = r.motion;
    tracker_.SetMapping(
        mapping_.AfterCameraMotion(r.motion.CurrentFromReference()));
    return true;
  }

  const TestPlan* plan_;
  PlaneMapping mapping_;
  std::unique_ptr<BenchRegistration> registration_;
  double mm_per_px_;
  std::unique_ptr<VideoReader> reader_;
  HeadTracker tracker_;
  const std::vector<SnapshotTime>* snapshot_times_;
  std::atomic<int64_t>* frames_done_;
  std::vector<FrameSample> frames_;
  std::vector<FrameSnapshot> snapshots_;
  int missing_dots_ = 0, rejected_blobs_ = 0, full_frame_frames_ = 0;
  int unregistered_frames_ = 0;
  std::string unregistered_reason_;
  bool first_frame_complete_ = false;
};

// Replaces each registered frame's own camera motion by the camera's path
// (SmoothCameraPath: knocks kept, a codec's slow wobble of the static edges
// averaged) and measures its heads again through it.
void FollowCameraPath(const PlaneMapping& mapping, const HeadTracker& tracker,
                      const CameraPathOptions& options, double frame_interval_s,
                      std::vector<FrameSample>* frames) {
  std::vector<double> times;
  std::vector<CameraMotion> raw;
  std::vector<bool> valid;
  for (const FrameSample& f : *frames) {
    times.push_back(f.time_s);
    raw.push_back(f.camera_motion);
    valid.push_back(f.registered);
  }
  const std::vector<CameraMotion> path = SmoothCameraPath(
      mapping.intrinsics(), times, raw, valid, 2.5 * frame_interval_s, options);
  for (size_t i = 0; i < frames->size(); ++i) {
    FrameSample& f = (*frames)[i];
    if (!f.registered) continue;
    f.camera_motion = path[i];
    f.camera_shift_px = path[i].ShiftPx(mapping.intrinsics());
    f.camera_roll_rad = path[i].roll_rad();
    const PlaneMapping moved =
        mapping.AfterCameraMotion(path[i].CurrentFromReference());
    for (size_t h = 0; h < f.heads.size(); ++h) {
      tracker.Remap(static_cast<int>(h), moved, &f.heads[h].observation);
    }
  }
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

PlaneMapping PlanMapping(
    const TestPlan& plan, const std::string& video_path,
    const CameraIntrinsics& intrinsics, int tag_frames, std::string* source,
    std::optional<std::array<Eigen::Vector2d, 4>>* tag_corners) {
  const CalibrationSpec& c = plan.calibration;
  if (c.tag) {
    *source = fmt::format("tag {}", c.tag->id);
    const std::array<Eigen::Vector2d, 4> corners =
        TagCornersFromVideo(plan, video_path, tag_frames);
    if (tag_corners != nullptr) *tag_corners = corners;
    return PlaneMapping::FromTag(intrinsics, corners, c.tag->size_mm,
                                 c.plane_offset_mm);
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
  VideoReaderOptions probe;
  probe.want_luma = probe.want_bgr = false;
  const VideoInfo info = VideoReader(video_path, probe).info();
  const CameraIntrinsics intrinsics =
      PlanIntrinsics(plan, info.width_px, info.height_px);
  VideoMeasurement m;
  m.video_path = video_path;
  m.fps = info.fps;
  m.frame_interval_s = info.frame_interval_s;
  m.video_format = info.Description();
  const CalibrationSpec& c = plan.calibration;
  std::optional<std::array<Eigen::Vector2d, 4>> tag_corners;
  const PlaneMapping mapping =
      PlanMapping(plan, video_path, intrinsics, options.tag_frames,
                  &m.scale_source, &tag_corners);

  // Each measurer registers with its own copy, to one shared reference.
  std::optional<RegistrationReference> reference =
      options.register_frames ? std::optional(MakeRegistrationReference(
                                    plan, video_path, mapping, tag_corners))
                              : std::nullopt;
  const auto registration = [&]() -> std::unique_ptr<BenchRegistration> {
    if (!reference) return nullptr;
    return std::make_unique<BenchRegistration>(
        intrinsics, reference->luma, reference->static_mask, reference->tag,
        options.registration);
  };
  // Without a tag, only static structure can register the frames; a plan
  // with neither (a scale, a plain table) keeps the still camera it always
  // assumed, and says so.
  std::string why_still = "off: the camera is taken to be still";
  if (reference && !reference->tag &&
      registration()->patch_count() < options.registration.min_patches) {
    reference.reset();
    why_still =
        "off: no tag in the plan and too little static structure in view; "
        "the camera is taken to be still";
  }
  m.mm_per_px = mapping.MmPerPixelAt(
      Eigen::Vector2d(intrinsics.width_px / 2.0, intrinsics.height_px / 2.0));
  m.mapping = mapping;
  const double half_frame_s = 0.5 * info.frame_interval_s;
  std::vector<SnapshotTime> snapshot_times;
  for (const double t : options.snapshot_times_s) {
    snapshot_times.push_back(
        {t, info.frame_times_s.empty()
                ? t
                : info.frame_times_s[info.NearestFrame(t)]});
  }
  std::sort(snapshot_times.begin(), snapshot_times.end(),
            [](const SnapshotTime& a, const SnapshotTime& b) {
              return a.frame_s < b.frame_s;
            });

  // Every frame, or the frames of the spans in time order (overlapping ones
  // merged, those beyond the video dropped).
  m.every_frame = options.spans.empty();
  std::vector<TimeSpan> spans;
  if (m.every_frame) {
    spans.push_back({-half_frame_s, INFINITY});
  } else {
    spans = MergeSpans(options.spans, info.duration_s, half_frame_s);
  }
  int64_t frames_wanted = info.frame_count;
  if (!m.every_frame) {
    frames_wanted = 0;
    for (const TimeSpan& span : spans) {
      frames_wanted += static_cast<int64_t>(
          std::ceil((std::min(span.end_s, info.duration_s) - span.start_s) /
                    info.frame_interval_s));
    }
  }
  ProgressBar progress("measure", frames_wanted, options.progress);
  std::atomic<int64_t> frames_done{0};
  const int jobs =
      m.every_frame ? 1
                    : static_cast<int>(std::min<size_t>(
                          std::max<size_t>(spans.size(), 1),
                          std::max(1u, std::thread::hardware_concurrency())));
  std::vector<SpanMeasurer> measurers;
  measurers.reserve(jobs);  // the copies below refer to the first one
  measurers.emplace_back(
      plan, video_path, mapping, m.mm_per_px,
      HeadTracker(mapping, PlanHeadMarkers(plan), options.tracker),
      registration(), snapshot_times, m.every_frame ? 0 : 1, &frames_done);
  measurers.front().RequireCompleteFirstFrame();
  m.registers_frames = reference.has_value();
  m.registration =
      reference
          ? fmt::format(
                "every frame, by {}{} static patches",
                reference->tag ? fmt::format("tag {} and ", c.tag->id) : "",
                measurers.front().patch_count())
          : "off: the camera is taken to be still";
  if (m.every_frame) {
    measurers.front().Measure(spans.front(), false,
                              [&] { progress.Update(frames_done); });
  } else if (!spans.empty()) {
    // The first frame alone: it sets the heads' references (rotation, dot
    // offsets) that every later frame is measured against. Then the windows
    // in parallel, each worker a share of them in time order with its own
    // single-threaded decoder (after a seek, frame threads never fill up)
    // and a copy of the tracker; the first continues where it stopped.
    measurers.front().Measure(
        {spans.front().start_s, spans.front().start_s + half_frame_s}, true,
        [] {});
    for (int j = 1; j < jobs; ++j) {
      measurers.emplace_back(plan, video_path, mapping, m.mm_per_px,
                             measurers.front().tracker(), registration(),
                             snapshot_times, 1, &frames_done);
    }
    RunParallelTasks(
        jobs, jobs,
        [&](int j) {
          for (size_t i = spans.size() * j / jobs;
               i < spans.size() * (j + 1) / jobs; ++i) {
            measurers[j].Measure(spans[i], i > 0, [] {});
          }
        },
        [&] { progress.Update(frames_done); });
  }
  progress.Finish();
  for (SpanMeasurer& measurer : measurers) measurer.MoveInto(&m);
  if (reference) {
    FollowCameraPath(mapping, measurers.front().tracker(), options.camera_path,
                     info.frame_interval_s, &m.frames);
  }
  if (m.frames.empty())
    throw InputError(video_path + ": the video has no frames");
  if (2 * m.unregistered_frames > static_cast<int>(m.frames.size())) {
    throw InputError(fmt::format(
        "{}: {} of {} frames could not be registered to the bench ({}: {}); "
        "keep the plan's tag uncovered and in view for the whole video",
        video_path, m.unregistered_frames, m.frames.size(),
        UnregisteredSpans(m.frames), m.unregistered_reason));
  }
  m.last_frame_s = m.every_frame ? m.frames.back().time_s : info.LastFrameS();

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

std::string UnregisteredSpans(const std::vector<FrameSample>& frames) {
  std::vector<std::string> spans;
  for (size_t i = 0; i < frames.size();) {
    if (frames[i].registered) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j + 1 < frames.size() && !frames[j + 1].registered) ++j;
    spans.push_back(i == j ? fmt::format("frame {} (t = {:.3f} s)",
                                         frames[i].frame, frames[i].time_s)
                           : fmt::format("frames {}-{} (t = {:.3f}-{:.3f} s)",
                                         frames[i].frame, frames[j].frame,
                                         frames[i].time_s, frames[j].time_s));
    i = j + 1;
  }
  std::string text;
  for (size_t k = 0; k < spans.size() && k < 5; ++k) {
    text += (k > 0 ? ", " : "") + spans[k];
  }
  if (spans.size() > 5) {
    text += fmt::format(" and {} more stretches", spans.size() - 5);
  }
  return text;
}

const FrameSample* FindFrame(const VideoMeasurement& measurement,
                             double time_s) {
  const std::vector<FrameSample>& frames = measurement.frames;
  const auto it = std::lower_bound(
      frames.begin(), frames.end(), time_s,
      [](const FrameSample& f, double t) { return f.time_s < t; });
  const FrameSample* nearest = nullptr;
  if (it != frames.end()) nearest = &*it;
  if (it != frames.begin() &&
      (nearest == nullptr ||
       time_s - std::prev(it)->time_s < nearest->time_s - time_s)) {
    nearest = &*std::prev(it);
  }
  return nearest != nullptr && std::abs(nearest->time_s - time_s) <=
                                   measurement.frame_interval_s + 1e-9
             ? nearest
             : nullptr;
}

FrameSnapshot SnapshotHeads(const FrameSource& frame, const FrameSample& sample,
                            const TestPlan& plan, double mm_per_px,
                            double requested_s) {
  FrameSnapshot snapshot;
  snapshot.requested_s = requested_s;
  snapshot.frame = sample.frame;
  snapshot.time_s = sample.time_s;
  for (size_t h = 0; h < sample.heads.size(); ++h) {
    const HeadObservation& obs = sample.heads[h].observation;
    HeadCrop& crop = snapshot.heads.emplace_back();
    std::vector<Eigen::Vector2d> dots;
    for (const DotObservation& dot : obs.dots) {
      if (dot.found) dots.push_back(dot.pixel);
    }
    const cv::Rect box = BoxAround(
        dots, 2.5 * plan.markers[h].dot_diameter_mm / std::max(mm_per_px, 1e-9),
        frame.luma().size());
    if (box.empty()) continue;
    crop.bgr = frame.BgrRegion(box);
    crop.origin_px = Eigen::Vector2d(box.x, box.y);
  }
  return snapshot;
}

void CaptureSnapshots(const TestPlan& plan, const std::vector<double>& times_s,
                      VideoMeasurement* measurement) {
  std::vector<double> times = times_s;
  std::sort(times.begin(), times.end());
  VideoReaderOptions reader_options;
  reader_options.want_bgr = false;
  VideoReader reader(measurement->video_path, reader_options);
  for (double t : times) {
    const FrameSample* sample = FindFrame(*measurement, t);
    if (sample == nullptr) continue;  // not measured: nothing to annotate
    const VideoFrame frame = reader.SeekTo(sample->time_s);
    measurement->snapshots.push_back(
        SnapshotHeads(VideoFrameSource(&reader, &frame), *sample, plan,
                      measurement->mm_per_px, t));
  }
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
      "rotation_rad,binary_y_mm,binary_z_mm,full_frame,registered,"
      "camera_dx_px,camera_dy_px,camera_roll_rad,note\n";
  for (const FrameSample& f : measurement.frames) {
    for (size_t h = 0; h < f.heads.size(); ++h) {
      const HeadSample& s = f.heads[h];
      const HeadObservation& o = s.observation;
      std::string note = o.note;
      std::replace(note.begin(), note.end(), ',', ';');
      csv += fmt::format(
          "{},{:.6f},{},{:.4f},{:.4f},{:.5f},{:.5f},{:.5f},{},{},{:.6f},"
          "{:.5f},{:.5f},{},{},{:.4f},{:.4f},{:.7f},{}\n",
          f.frame, f.time_s, plan.mechanism.heads[plan.markers[h].head].name,
          o.pixel.x(), o.pixel.y(), s.displacement_mm.x(),
          s.displacement_mm.y(), o.sigma_mm, o.dots_found, o.dots.size(),
          o.rotation_rad, s.binary_displacement_mm.x(),
          s.binary_displacement_mm.y(), o.full_frame ? 1 : 0,
          f.registered ? 1 : 0, f.camera_shift_px.x(), f.camera_shift_px.y(),
          f.camera_roll_rad, note);
    }
  }
  return csv;
}

}  // namespace softbench
