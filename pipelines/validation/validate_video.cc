#include "pipelines/validation/validate_video.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <future>
#include <iterator>

#include "pipelines/measurement/snapshots.h"
#include "util/check.h"
#include "util/file_digest.h"
#include "util/input_error.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

// The stride of the crops kept for the windows' middles while the times are
// unknown [s], and how far from its window's middle a kept crop may be:
// three frames at 30 fps, or a quarter of a short window. A middle without
// one that near is sought.
double WindowFrameStrideS(const TestPlan& plan) {
  return std::min(0.1, 0.25 * plan.window_s);
}

// The measurement's options: with the times known, the windows' crops are
// kept on the way and, windows only, their frames are all that is read.
VideoMeasurementOptions MeasurementOptions(
    const TestPlan& plan, const VideoReader& reader, bool times_known,
    const VideoValidationOptions& options) {
  VideoMeasurementOptions measure;
  measure.progress = options.progress;
  measure.register_frames = options.register_frames;
  measure.rest_s = times_known ? *plan.tests.front().actuate_s : options.rest_s;
  if (!times_known) {
    measure.window_frames = WindowFrameKeeperOptions{
        .window_s = plan.window_s, .stride_s = WindowFrameStrideS(plan)};
    return measure;
  }
  const auto windows = PlanWindows(plan, reader.info().LastFrameS());
  measure.snapshot_times_s = WindowMiddles(windows);
  if (options.windows_only) {
    for (const auto& test : windows) {
      for (const WindowSummary& w : test) {
        measure.spans.push_back({w.start_s, w.end_s});
      }
    }
    // Key frames around which a still head shows the codec's error, when
    // the windows hold too few (codec_jump_spans.h).
    for (const TimeSpan& span :
         PlanCodecJumpSpans(plan, measure.spans, reader.info(),
                            options.scoring.min_codec_jumps,
                            options.codec_jump_spans)
             .spans) {
      measure.spans.push_back(span);
    }
  }
  return measure;
}

// Gives the plan's tests their times from the motion or from the log's
// holds aligned to it; returns where they came from.
std::string TimesFromVideo(const VideoMeasurement& m,
                           const std::optional<PressureLogTimes>& log,
                           const TestPointDetectionOptions& options,
                           TestPlan* plan) {
  const TestPointDetection detection =
      DetectTestPoints(m, static_cast<int>(plan->tests.size()), options);
  if (!detection.found) {
    const size_t lost = m.damaged_frames + m.lost_frame_times_s.size();
    // Damaged frames make motion where there was none, or hide it: named
    // first, as the cause.
    throw InputError(
        lost == 0
            ? m.video_path + ": " + detection.why_not
            : fmt::format("{}: {} frames were lost to damaged video data, so "
                          "the test points cannot be told from the motion "
                          "({}); re-copy or re-export the video, or give the "
                          "tests' actuate_s and release_s",
                          m.video_path, lost, detection.why_not));
  }
  if (!log) {
    for (size_t i = 0; i < plan->tests.size(); ++i) {
      plan->tests[i].actuate_s = detection.points[i].actuate_s;
      plan->tests[i].release_s = detection.points[i].release_s;
    }
    return fmt::format("the motion (heads beyond {:.3f} mm)",
                       detection.threshold_mm);
  }
  const PressureLogAlignment alignment =
      AlignPressureLog(log->holds, detection, log->path);
  for (size_t i = 0; i < plan->tests.size(); ++i) {
    plan->tests[i].actuate_s = log->holds[i].start_s + alignment.offset_s;
    plan->tests[i].release_s = log->holds[i].end_s + alignment.offset_s;
  }
  return fmt::format(
      "the pressure log {}, its clock {:+.3f} s from the video's (steps in "
      "the motion within {:.3f} s of it)",
      log->path, alignment.offset_s, alignment.spread_s);
}

// The files behind a validation, by role, without their digests yet.
std::vector<InputFile> InputFiles(const TestPlan& plan,
                                  const std::string& video_path,
                                  const std::optional<PressureLogTimes>& log) {
  const std::string paths[] = {video_path,
                               plan.path,
                               plan.mechanism_path,
                               plan.constants_path,
                               log ? log->path : std::string(),
                               plan.calibration.intrinsics_path};
  std::vector<InputFile> files;
  for (size_t i = 0; i < std::size(kInputRoles); ++i) {
    if (!paths[i].empty()) files.push_back({kInputRoles[i], paths[i], ""});
  }
  return files;
}

}  // namespace

std::optional<std::string> VideoValidationOptions::Problem() const {
  if (!(rest_s > 0.0)) return "rest_s: must be > 0 s";
  if (auto problem = scoring.Problem()) return "scoring: " + *problem;
  if (auto problem = detection.Problem()) return "detection: " + *problem;
  if (auto problem = codec_jump_spans.Problem()) {
    return "codec_jump_spans: " + *problem;
  }
  if (auto problem = lift_correction.Problem()) {
    return "lift_correction: " + *problem;
  }
  return std::nullopt;
}

VideoValidation ValidateVideo(TestPlan plan, const std::string& video_path,
                              const std::optional<PressureLogTimes>& log,
                              const VideoValidationOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  const bool times_known = plan.HasTimes() && !log;
  if (options.windows_only && !times_known) {
    throw InputError(fmt::format(
        "{}: --windows-only needs the test times before reading the video; "
        "give every test actuate_s and release_s in the plan (times from the "
        "motion or a pressure log need every frame)",
        plan.path));
  }
  if (times_known) CheckWindowsFitTheTimes(plan);
  // The record of the inputs, hashed on a thread of its own while the
  // video is read (a gigabyte takes about a second). When the measurement
  // fails, the hashing is told to stop before its future is waited for, so
  // the error is not held up by reading the rest of a large file.
  std::atomic<bool> stop_hashing{false};
  std::future<std::vector<InputFile>> inputs = std::async(
      std::launch::async,
      [files = InputFiles(plan, video_path, log), &stop_hashing]() mutable {
        for (InputFile& file : files) {
          std::optional<std::string> digest =
              Sha256OfFile(file.path, &stop_hashing);
          if (!digest) break;
          file.sha256 = std::move(*digest);
        }
        return files;
      });
  const struct StopHashingOnFailure {
    std::atomic<bool>* stop;
    ~StopHashingOnFailure() {
      if (std::uncaught_exceptions() > 0) stop->store(true);
    }
  } stop_on_failure{&stop_hashing};
  VideoReader reader(video_path,
                     MeasurementReaderOptions(!options.windows_only));
  VideoMeasurement m = MeasureVideo(
      plan, &reader, MeasurementOptions(plan, reader, times_known, options));
  const std::string times_source =
      times_known ? "the plan"
                  : TimesFromVideo(m, log, options.detection, &plan);
  auto [result, lift] = ScoreTestsCorrectingLift(plan, options.scoring,
                                                 options.lift_correction, &m);
  result.times_source = times_source;
  if (!times_known) {
    // The plan has its times now: the windows' crops, from the same reader.
    CaptureSnapshots(plan, WindowMiddles(PlanWindows(plan, m.last_frame_s)),
                     WindowFrameStrideS(plan), &reader, &m);
  }
  return {std::move(plan), std::move(m), std::move(result), inputs.get(), lift};
}

}  // namespace softbench
