#include "pipelines/measurement/video_measurement.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <future>
#include <memory>

#include "pipelines/measurement/distortion_check.h"
#include "pipelines/measurement/plan_camera.h"
#include "pipelines/measurement/span_measurer.h"
#include "util/check.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
#include "util/progress.h"
#include "util/statistics.h"

namespace softbench {

std::optional<std::string> VideoMeasurementOptions::Problem() const {
  if (tag_frames < 1) return "tag_frames must be >= 1";
  if (!(rest_s > 0.0)) return "rest_s must be > 0";
  if (auto problem = registration.Problem()) return problem;
  if (auto problem = camera_path.Problem()) return problem;
  if (auto problem = plate_pose.Problem()) return "plate_pose: " + *problem;
  if (!(plate_dot_sigma_px > 0.0)) return "plate_dot_sigma_px must be > 0";
  if (auto problem = camera_processing.Problem()) {
    return "camera_processing: " + *problem;
  }
  if (auto problem = tag_model.Problem()) return "tag_model: " + *problem;
  if (window_frames) {
    if (auto problem = window_frames->Problem()) {
      return "window_frames: " + *problem;
    }
  }
  return tracker.Problem();
}

namespace {

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

// The frames' own registrations (before the camera's path replaces them).
RegisteredFrames RegisteredFramesOf(const std::vector<FrameSample>& frames,
                                    const CameraIntrinsics& intrinsics) {
  RegisteredFrames r;
  for (const FrameSample& f : frames) {
    r.times_s.push_back(f.time_s);
    r.shifts_px.push_back(f.camera_motion.ShiftPx(intrinsics));
    r.sums.push_back(f.shear_sums);
    r.index.push_back(f.frame);
    r.registered.push_back(f.registered);
  }
  return r;
}

// `motion` as the camera was `delay_s` later, moving the image at
// `velocity_px_s`: a pan and tilt of delay x velocity more.
CameraMotion MotionLater(const CameraIntrinsics& intrinsics,
                         const CameraMotion& motion, double delay_s,
                         const Eigen::Vector2d& velocity_px_s) {
  CameraMotion later = motion;
  later.rotation_rad +=
      CameraMotion::FromImageShift(intrinsics, delay_s * velocity_px_s, 0.0)
          .rotation_rad;
  return later;
}

// Replaces each registered frame's own camera motion by the camera's path
// (SmoothCameraPath: knocks kept, tremor followed, a codec's slow wobble of
// a still camera's static edges averaged) and measures its heads again
// through `mapping` (the tag over the whole video) moved by it. Under a
// rolling shutter that was seen, each frame's motion is first freed of
// the shear its fit took up (RollingShutter::MiddleLineMotion), and each
// head is measured through the camera's motion when its line was read: the
// frame's, moved on by the line's delay times the camera's image velocity
// (`velocities`, per frame). `registered` is the frames' RegisteredFramesOf.
void FollowCameraPath(
    const PlaneMapping& mapping, const HeadTracker& tracker,
    const CameraPathOptions& options, double frame_interval_s,
    const RegisteredFrames& registered, const RollingShutter& shutter,
    const std::vector<std::optional<Eigen::Vector2d>>& velocities,
    std::vector<FrameSample>* frames) {
  std::vector<CameraMotion> raw;
  for (size_t i = 0; i < frames->size(); ++i) {
    const FrameSample& f = (*frames)[i];
    raw.push_back(velocities[i]
                      ? shutter.MiddleLineMotion(f.camera_motion, f.shear_sums,
                                                 *velocities[i])
                      : f.camera_motion);
  }
  const CameraIntrinsics& k = mapping.intrinsics();
  const std::vector<CameraMotion> path =
      SmoothCameraPath(k, registered.times_s, raw, registered.registered,
                       2.5 * frame_interval_s, options);
  const Eigen::Vector2d size_px(k.width_px, k.height_px);
  for (size_t i = 0; i < frames->size(); ++i) {
    FrameSample& f = (*frames)[i];
    if (!f.registered) continue;
    f.camera_motion = path[i];
    f.camera_shift_px = path[i].ShiftPx(k);
    f.camera_roll_rad = path[i].roll_rad();
    const PlaneMapping moved =
        mapping.AfterCameraMotion(path[i].CurrentFromReference());
    for (size_t h = 0; h < f.heads.size(); ++h) {
      HeadObservation& observation = f.heads[h].observation;
      const double delay_s = shutter.ReadDelayS(observation.pixel, size_px);
      if (delay_s == 0.0 || !velocities[i] || !observation.pixel.allFinite()) {
        tracker.Remap(static_cast<int>(h), moved, &observation);
        continue;
      }
      const CameraMotion read =
          MotionLater(k, path[i], delay_s, *velocities[i]);
      tracker.Remap(static_cast<int>(h),
                    mapping.AfterCameraMotion(read.CurrentFromReference()),
                    &observation);
    }
  }
}

// The measurement's video facts, before any frame is measured.
VideoMeasurement StartMeasurement(const VideoReader& reader) {
  const VideoInfo& info = reader.info();
  VideoMeasurement m;
  m.video_path = reader.path();
  m.fps = info.fps;
  m.frame_interval_s = info.frame_interval_s;
  m.video_format = info.Description();
  return m;
}

// The snapshots' times and their nearest frames' times, in frame order.
std::vector<SnapshotTime> SnapshotTimes(const VideoInfo& info,
                                        const std::vector<double>& times_s) {
  std::vector<SnapshotTime> snapshot_times;
  for (const double t : times_s) {
    snapshot_times.push_back(
        {t, info.frame_times_s.empty()
                ? t
                : info.frame_times_s[info.NearestFrame(t)]});
  }
  std::sort(snapshot_times.begin(), snapshot_times.end(),
            [](const SnapshotTime& a, const SnapshotTime& b) {
              return a.frame_s < b.frame_s;
            });
  return snapshot_times;
}

// Every frame, or the frames of the spans in time order (overlapping ones
// merged, those beyond the video dropped); `frames_wanted` receives their
// number, for the progress bar.
std::vector<TimeSpan> MeasuredSpans(const VideoInfo& info,
                                    const std::vector<TimeSpan>& requested,
                                    int64_t* frames_wanted) {
  const double half_frame_s = 0.5 * info.frame_interval_s;
  if (requested.empty()) {
    *frames_wanted = info.frame_count;
    return {{-half_frame_s, INFINITY}};
  }
  std::vector<TimeSpan> spans =
      MergeSpans(requested, info.duration_s, half_frame_s);
  *frames_wanted = 0;
  for (const TimeSpan& span : spans) {
    *frames_wanted += static_cast<int64_t>(
        std::ceil((std::min(span.end_s, info.duration_s) - span.start_s) /
                  info.frame_interval_s));
  }
  return spans;
}

// What registers the frames to the bench: the reference from the first
// frame, and the registration each measurer copies (made once: the windows'
// workers and the check for enough structure share its patches).
struct Registrations {
  std::optional<RegistrationReference> reference;
  BenchRegistrationOptions options;
  std::unique_ptr<const BenchRegistration> prototype;  // with a reference

  std::unique_ptr<BenchRegistration> Make() const {
    return prototype ? prototype->Clone() : nullptr;
  }
};

// Without a tag, only static structure can register the frames; a plan
// with neither (a scale, a plain table) keeps the still camera it always
// assumed, and says so in `why_still`.
Registrations MakeRegistrations(
    const TestPlan& plan, const FrameSource& first, const PlaneMapping& mapping,
    const CameraIntrinsics& intrinsics,
    const std::optional<std::array<Eigen::Vector2d, 4>>& tag_corners,
    const VideoMeasurementOptions& options, std::string* why_still) {
  Registrations r{std::nullopt, options.registration, nullptr};
  r.options.tag.luma_encoding = first.luma_encoding();
  r.options.patches.luma_encoding = first.luma_encoding();
  *why_still = "off: the camera is taken to be still";
  if (!options.register_frames) return r;
  r.reference = MakeRegistrationReference(plan, first, mapping, tag_corners);
  r.prototype = std::make_unique<const BenchRegistration>(
      intrinsics, first.luma(), r.reference->static_mask, r.reference->tag,
      r.options);
  if (!r.reference->tag &&
      r.prototype->patch_count() < options.registration.min_patches) {
    r.reference.reset();
    r.prototype.reset();
    *why_still =
        "off: no tag in the plan and too little static structure in view; "
        "the camera is taken to be still";
  }
  return r;
}

// Measures through `mapping` from here on: m's mapping, and its scale at
// the image's centre.
void SetMapping(const PlaneMapping& mapping, const CameraIntrinsics& intrinsics,
                VideoMeasurement* m) {
  m->mapping = mapping;
  m->mm_per_px = mapping.MmPerPixelAt(
      Eigen::Vector2d(intrinsics.width_px / 2.0, intrinsics.height_px / 2.0));
}

// The plan's tag mapping again from the tag's corners in every registered
// frame (AverageTagCorners), once there are at least `min_frames` of them:
// the first frames' mapping tilts the plane by a few tenths of a degree on
// codec noise, which bends the scale across the field (0.065 % at a head
// 67 mm from the tag). Sets `m`'s mapping and scale, and `tag_corners` to
// the corners it was made from (scaled by `tag_scale`, the tag fitted
// whole against the midlines, where it was); else keeps them.
PlaneMapping TagMappingOverTheVideo(
    const TestPlan& plan, const CameraIntrinsics& intrinsics,
    const Registrations& registrations, int min_frames,
    const Eigen::Vector2d& tag_scale, VideoMeasurement* m,
    std::optional<std::array<Eigen::Vector2d, 4>>* tag_corners) {
  if (!registrations.reference || !registrations.reference->tag) {
    return *m->mapping;
  }
  std::vector<std::array<Eigen::Vector2d, 4>> seen;
  for (const FrameSample& f : m->frames) {
    if (f.registered && f.tag_corners) seen.push_back(*f.tag_corners);
  }
  if (static_cast<int>(seen.size()) < min_frames) return *m->mapping;
  const CalibrationSpec& c = plan.calibration;
  *tag_corners = AverageTagCorners(registrations.reference->tag->corners, seen);
  **tag_corners = ScaledTagCorners(**tag_corners, tag_scale);
  SetMapping(PlaneMapping::FromTag(intrinsics, **tag_corners, c.tag->size_mm,
                                   c.plane_offset_mm),
             intrinsics, m);
  return *m->mapping;
}

// A windows worker's reader after the first's, opened and sought to the
// worker's first span on a thread of its own while the first worker reads
// the tag, chooses the patches and measures the first frame: a seek decodes
// from the key frame before the span (up to a GOP of frames), so without it
// the other workers would start that much later. One decoder thread: after
// a seek, frame threads never fill up.
class WindowReader {
 public:
  WindowReader(const std::string& path, double span_start_s)
      : sought_(std::async(std::launch::async, [this, path, span_start_s] {
          reader_ = std::make_unique<VideoReader>(
              path, VideoReaderOptions{
                        .want_luma = true, .want_bgr = false, .threads = 1});
          return reader_->SeekTo(span_start_s);
        })) {}
  WindowReader(const WindowReader&) = delete;
  WindowReader& operator=(const WindowReader&) = delete;

  // Waits for the seek; the reader, and in `frame` the frame it gave.
  VideoReader* Take(VideoFrame* frame) {
    *frame = sought_.get();
    return reader_.get();
  }

 private:
  std::unique_ptr<VideoReader> reader_;  // set on `sought_`'s thread
  std::future<VideoFrame> sought_;  // after reader_: waited for before it goes
};

// How many workers measure the windows, one per core.
size_t WindowJobs(const std::vector<TimeSpan>& spans) {
  return std::min<size_t>(spans.size(), CoreCount());
}

// The readers of the windows' workers after the first, each sought to its
// first span (span j for worker j).
std::vector<std::unique_ptr<WindowReader>> OpenWindowReaders(
    const std::string& path, const std::vector<TimeSpan>& spans) {
  std::vector<std::unique_ptr<WindowReader>> readers;
  for (size_t j = 1; j < WindowJobs(spans); ++j) {
    readers.push_back(std::make_unique<WindowReader>(path, spans[j].start_s));
  }
  return readers;
}

// The windows in parallel: the first frame alone (it sets the heads'
// references - rotation, dot offsets - that every later frame is measured
// against), then each worker one span at a time, the next not yet taken,
// with its own reader and a copy of the tracker; the first continues where
// it stopped. Taken in whatever order the workers free up, the spans are
// measured alike: after a seek a span depends on none before it
// (SpanMeasurer::Measure).
void MeasureWindows(const std::vector<TimeSpan>& spans, double half_frame_s,
                    const std::function<SpanMeasurer(VideoReader*)>& make,
                    const std::vector<std::unique_ptr<WindowReader>>& readers,
                    std::vector<SpanMeasurer>* measurers, ProgressBar* progress,
                    const std::atomic<int64_t>& frames_done) {
  SpanMeasurer& first = measurers->front();
  first.Measure({spans.front().start_s, spans.front().start_s + half_frame_s},
                SpanMeasurer::Start::kSeek, nullptr, [] {});
  const size_t jobs = readers.size() + 1;
  std::vector<VideoFrame> sought(jobs);
  for (size_t j = 1; j < jobs; ++j) {
    measurers->push_back(make(readers[j - 1]->Take(&sought[j])));
  }
  std::atomic<size_t> next{jobs};
  RunParallelTasks(
      static_cast<int>(jobs), static_cast<int>(jobs),
      [&](int j) {
        SpanMeasurer& measurer = (*measurers)[j];
        measurer.Measure(spans[j],
                         j == 0 ? SpanMeasurer::Start::kReadOn
                                : SpanMeasurer::Start::kSought,
                         &sought[j], [] {});
        for (size_t i = next++; i < spans.size(); i = next++) {
          measurer.Measure(spans[i], SpanMeasurer::Start::kSeek, nullptr,
                           [] {});
        }
      },
      [&] { progress->Update(frames_done); });
}

// What the measurers measured, into `m`: the frames in time order (the
// windows' workers took spans out of order), the reason for unregistered
// frames that of the earliest.
void GatherMeasurers(std::vector<SpanMeasurer>* measurers,
                     VideoMeasurement* m) {
  std::vector<SpanMeasurer*> order;
  for (SpanMeasurer& measurer : *measurers) order.push_back(&measurer);
  std::stable_sort(order.begin(), order.end(),
                   [](const SpanMeasurer* a, const SpanMeasurer* b) {
                     return a->first_unregistered_s() <
                            b->first_unregistered_s();
                   });
  for (SpanMeasurer* measurer : order) measurer->MoveInto(m);
  if (measurers->size() == 1) return;
  std::sort(m->frames.begin(), m->frames.end(),
            [](const FrameSample& a, const FrameSample& b) {
              return a.time_s < b.time_s;
            });
  std::sort(m->snapshots.begin(), m->snapshots.end(),
            [](const FrameSnapshot& a, const FrameSnapshot& b) {
              return a.time_s < b.time_s;
            });
}

// Motion within a rest [mm] (5-95 % range) that says it was no rest: far
// above tremor and codec noise (about 0.002 mm), far below a test's motion.
constexpr double kMaxRestMotionMm = 0.05;

// Each head's rest position: the median over the frames before the first
// actuation (plan times) or the first `rest_s`; then every frame's
// displacements from it.
void SetDisplacements(const TestPlan& plan, double rest_s,
                      VideoMeasurement* m) {
  double rest_end = rest_s;
  if (plan.HasTimes()) {
    rest_end = *plan.tests.front().actuate_s;
    for (const TestPoint& t : plan.tests)
      rest_end = std::min(rest_end, *t.actuate_s);
  }
  for (size_t h = 0; h < plan.markers.size(); ++h) {
    std::vector<double> ys, zs;
    // Per dot and axis: the dots at rest, the reference of the head's pose
    // out of the plane (MeasurePlatePoses).
    std::vector<std::array<std::vector<double>, 2>> dots;
    for (const FrameSample& f : m->frames) {
      const HeadObservation& obs = f.heads[h].observation;
      if (f.time_s < rest_end && obs.complete) {
        ys.push_back(obs.position_mm.x());
        zs.push_back(obs.position_mm.y());
        dots.resize(obs.dots.size());
        for (size_t d = 0; d < obs.dots.size(); ++d) {
          dots[d][0].push_back(obs.dots[d].plane_mm.x());
          dots[d][1].push_back(obs.dots[d].plane_mm.y());
        }
      }
    }
    if (ys.empty()) {
      throw InputError(fmt::format(
          "{}: head '{}' was not seen whole before t = {:.3f} s, so it has "
          "no rest position; start the video at rest",
          m->video_path, plan.mechanism.heads[plan.markers[h].head].name,
          rest_end));
    }
    // A rest taken by its length (no times in the plan) that runs into the
    // first actuation would measure every displacement from a point the
    // head never rested at: its motion inside the rest names the mistake.
    const double moved_mm = std::hypot(Quantile(ys, 0.95) - Quantile(ys, 0.05),
                                       Quantile(zs, 0.95) - Quantile(zs, 0.05));
    if (!plan.HasTimes() && moved_mm > kMaxRestMotionMm) {
      throw InputError(fmt::format(
          "{}: head '{}' moves by {:.3f} mm within the first {:.4g} s taken "
          "as its rest; give a rest (--rest-s) that ends before the first "
          "actuation",
          m->video_path, plan.mechanism.heads[plan.markers[h].head].name,
          moved_mm, rest_end));
    }
    m->rest_mm.emplace_back(Median(ys), Median(zs));
    std::vector<Eigen::Vector2d>& rest_dots = m->rest_dots_mm.emplace_back();
    for (const auto& dot : dots) {
      rest_dots.emplace_back(Median(dot[0]), Median(dot[1]));
    }
  }
  for (FrameSample& f : m->frames) {
    for (size_t h = 0; h < f.heads.size(); ++h) {
      HeadSample& s = f.heads[h];
      s.displacement_mm = s.observation.position_mm - m->rest_mm[h];
      s.binary_displacement_mm =
          s.observation.binary_position_mm - m->rest_mm[h];
    }
  }
}

// In every frame with the head complete, its pose against its dots at rest
// (SetDisplacements); the parallax it adds is taken out of the displacement
// when `options.correct_lift`.
void MeasurePlatePoses(const VideoMeasurementOptions& options,
                       VideoMeasurement* m) {
  const CameraAbovePlane camera = m->mapping->CameraAbove();
  // A mapping with no camera above the plane (none seen from a tag below
  // its dot plane) has no parallax to measure: lifts stay NaN.
  if (!camera.Found()) return;
  m->plate_pose = options.plate_pose;
  m->plate_dot_sigma_mm = options.plate_dot_sigma_px * m->mm_per_px;
  RunParallelTasks(
      static_cast<int>(m->frames.size()), 0,
      [&](int i) {
        FrameSample& f = m->frames[i];
        for (size_t h = 0; h < f.heads.size(); ++h) {
          HeadSample& s = f.heads[h];
          const std::vector<Eigen::Vector2d>& rest = m->rest_dots_mm[h];
          if (!s.observation.complete || rest.size() < 2) continue;
          std::vector<Eigen::Vector2d> dots;
          for (const DotObservation& d : s.observation.dots) {
            dots.push_back(d.plane_mm);
          }
          const PlatePose pose = FitPlatePose(
              rest, dots, camera, m->plate_dot_sigma_mm, m->plate_pose);
          if (!pose.found) continue;
          s.lift_mm = pose.lift_mm;
          s.tilt_rad = pose.tilt_rad;
          s.parallax_mm = pose.parallax_mm;
        }
      },
      [] {});
  if (options.correct_lift) TakeOutParallax(m);
}

// "every frame, by 40 static patches and tag 3 (the tag on one frame in 4
// while the camera is still)".
std::string RegistrationMethod(const TestPlan& plan,
                               const RegistrationReference& reference,
                               const BenchRegistrationOptions& options,
                               int patches) {
  if (!reference.tag) {
    return fmt::format("every frame, by {} static patches", patches);
  }
  return fmt::format(
      "every frame, by {} static patches and tag {}{}", patches,
      plan.calibration.tag->id,
      options.tag_stride == 1
          ? ""
          : fmt::format(" (the tag on one frame in {} while the camera is "
                        "still)",
                        options.tag_stride));
}

// Refuses a measurement with no frames, or with most of them not
// registered to the bench.
void CheckFramesRegistered(const VideoMeasurement& m) {
  if (m.frames.empty()) {
    throw InputError(m.video_path + ": the video has no frames");
  }
  if (2 * m.unregistered_frames > static_cast<int>(m.frames.size())) {
    throw InputError(fmt::format(
        "{}: {} of {} frames could not be registered to the bench ({}: {}); "
        "keep the plan's tag uncovered and in view for the whole video",
        m.video_path, m.unregistered_frames, m.frames.size(),
        UnregisteredSpans(m.frames), m.unregistered_reason));
  }
}

// After the frames: checks, rest positions, displacements and the dots'
// spacing against the layout (the distortion check).
void Finish(const TestPlan& plan, const VideoInfo& info,
            const VideoMeasurementOptions& options, VideoMeasurement* m) {
  CheckFramesRegistered(*m);
  m->last_frame_s =
      m->every_frame ? m->frames.back().time_s : info.LastFrameS();
  SetDisplacements(plan, options.rest_s, m);
  MeasurePlatePoses(options, m);
  m->distortion =
      CheckDistortion(plan, m->frames, m->scale_source,
                      m->mapping->CameraHeightMm(), m->camera_processing);
}

// Where the processing and small cells put the midlines' scale at risk
// (TagScaleAtRisk), fits the tag whole on the first frame and scales
// `tag_corners` and `mapping` by the fit's scale along each of the tag's
// axes; notes the tag's cells and the fit in `processing`. Returns the scale
// taken (ones where none was).
Eigen::Vector2d HoldTagScale(const TestPlan& plan, VideoReader* reader,
                             const VideoFrame& first,
                             const CameraIntrinsics& intrinsics,
                             const VideoMeasurementOptions& options,
                             std::array<Eigen::Vector2d, 4>* tag_corners,
                             PlaneMapping* mapping,
                             CameraProcessing* processing) {
  TagFittedWhole whole;
  const bool at_risk =
      TagScaleAtRisk(*tag_corners, options.camera_processing, *processing);
  if (at_risk) {
    const VideoFrameSource source(reader, &first);
    whole = FitTagWhole(plan, source.luma(), source.luma_encoding(),
                        *tag_corners, options.tag_model);
  }
  if (whole.fit.found) {
    *tag_corners = ScaledTagCorners(*tag_corners, whole.scale);
    *mapping = PlaneMapping::FromTag(intrinsics, *tag_corners,
                                     plan.calibration.tag->size_mm,
                                     plan.calibration.plane_offset_mm);
  }
  NoteTagCells(*tag_corners, options.camera_processing,
               at_risk ? std::optional<TagModelFit>(whole.fit) : std::nullopt,
               whole.ScaleChange(), processing);
  return whole.scale;  // ones where no fit was found
}

}  // namespace

void TakeOutParallax(VideoMeasurement* m) {
  SOFTBENCH_CHECK(!m->lift_corrected) << "the parallax is taken out once";
  for (FrameSample& f : m->frames) {
    for (HeadSample& s : f.heads) {
      if (s.parallax_mm.allFinite()) s.displacement_mm -= s.parallax_mm;
    }
  }
  m->lift_corrected = true;
}

VideoReaderOptions MeasurementReaderOptions(bool every_frame) {
  // Frame threads for a run through every frame; one thread for windows
  // (after a seek, frame threads never fill up).
  return {.want_luma = true, .want_bgr = false, .threads = every_frame ? 0 : 1};
}

VideoMeasurement MeasureVideo(const TestPlan& plan, VideoReader* reader,
                              const VideoMeasurementOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  const VideoInfo& info = reader->info();
  const CameraIntrinsics intrinsics =
      PlanIntrinsics(plan, info.width_px, info.height_px);
  int64_t frames_wanted = 0;
  const std::vector<TimeSpan> spans =
      MeasuredSpans(info, options.spans, &frames_wanted);
  const std::vector<std::unique_ptr<WindowReader>> window_readers =
      options.spans.empty() ? std::vector<std::unique_ptr<WindowReader>>()
                            : OpenWindowReaders(reader->path(), spans);
  VideoMeasurement m = StartMeasurement(*reader);
  std::optional<std::array<Eigen::Vector2d, 4>> tag_corners;
  std::vector<TagEdgeSigns> tag_signs;
  PlaneMapping mapping =
      PlanMapping(plan, reader, intrinsics, options.tag_frames, &m.scale_source,
                  &tag_corners, &tag_signs);
  m.camera_processing =
      DescribeCameraProcessing(tag_signs, options.camera_processing);
  if (!plan.calibration.tag) {
    m.camera_processing.why_not = "the plan has no tag to read it from";
  }
  m.camera_processing.rolling_shutter.why_not =
      "the frames were not registered to the bench";
  // Back to the first frame: the registration's reference, and where a run
  // through every frame starts.
  const VideoFrame first = reader->SeekTo(
      info.frame_times_s.empty() ? 0.0 : info.frame_times_s.front());
  const Eigen::Vector2d tag_scale =
      tag_corners ? HoldTagScale(plan, reader, first, intrinsics, options,
                                 &*tag_corners, &mapping, &m.camera_processing)
                  : Eigen::Vector2d::Ones();
  SetMapping(mapping, intrinsics, &m);
  std::string why_still;
  const Registrations registrations =
      MakeRegistrations(plan, VideoFrameSource(reader, &first), mapping,
                        intrinsics, tag_corners, options, &why_still);
  const std::vector<SnapshotTime> snapshot_times =
      SnapshotTimes(info, options.snapshot_times_s);
  m.every_frame = options.spans.empty();

  // Where the tag shows the codes sharpened, the dots are weighed in codes
  // (issue 28: sharpening's halos about a sharp edge move the light's
  // centroid, not the codes').
  HeadTrackerOptions tracker_options = options.tracker;
  tracker_options.centre.weigh_codes = m.camera_processing.sharpened;
  ProgressBar progress("measure", frames_wanted, options.progress);
  std::atomic<int64_t> frames_done{0};
  std::vector<SpanMeasurer> measurers;
  measurers.reserve(CoreCount());
  const auto make = [&](VideoReader* r) {
    return SpanMeasurer(
        plan, r, mapping, m.mm_per_px,
        measurers.empty()
            ? HeadTracker(mapping, PlanHeadMarkers(plan), tracker_options)
            : measurers.front().tracker(),
        registrations.Make(), snapshot_times, &frames_done);
  };
  measurers.push_back(make(reader));
  measurers.front().RequireCompleteFirstFrame();
  if (options.window_frames && m.every_frame) {
    measurers.front().KeepWindowFrames(*options.window_frames);
  }
  m.registers_frames = registrations.reference.has_value();
  m.registration = m.registers_frames
                       ? RegistrationMethod(plan, *registrations.reference,
                                            registrations.options,
                                            measurers.front().patch_count())
                       : why_still;
  if (m.every_frame) {
    measurers.front().Measure(spans.front(), SpanMeasurer::Start::kCurrent,
                              &first, [&] { progress.Update(frames_done); });
  } else if (!spans.empty()) {
    MeasureWindows(spans, 0.5 * info.frame_interval_s, make, window_readers,
                   &measurers, &progress, frames_done);
  }
  progress.Finish();
  GatherMeasurers(&measurers, &m);
  if (m.registers_frames) {
    const RollingShutterOptions& shutter_options =
        options.camera_processing.rolling_shutter;
    const RegisteredFrames r = RegisteredFramesOf(m.frames, intrinsics);
    const std::vector<std::optional<Eigen::Vector2d>> velocities =
        ImageVelocities(r, shutter_options);
    NameRollingShutter(EstimateRollingShutter(r, velocities, shutter_options),
                       &m.camera_processing);
    FollowCameraPath(
        TagMappingOverTheVideo(plan, intrinsics, registrations,
                               options.tag_frames, tag_scale, &m, &tag_corners),
        measurers.front().tracker(), options.camera_path, info.frame_interval_s,
        r, m.camera_processing.rolling_shutter, velocities, &m.frames);
  }
  m.intrinsics_sensitivity =
      IntrinsicsSensitivity(plan, intrinsics, *m.mapping, tag_corners);
  Finish(plan, info, options, &m);
  return m;
}

VideoMeasurement MeasureVideo(const TestPlan& plan,
                              const std::string& video_path,
                              const VideoMeasurementOptions& options) {
  VideoReader reader(video_path,
                     MeasurementReaderOptions(options.spans.empty()));
  return MeasureVideo(plan, &reader, options);
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

}  // namespace softbench
