#ifndef SOFTBENCH_PIPELINES_VALIDATION_VALIDATE_VIDEO_H_
#define SOFTBENCH_PIPELINES_VALIDATION_VALIDATE_VIDEO_H_

#include <optional>
#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/pressure_log.h"
#include "pipelines/measurement/test_point_detection.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/validation/codec_jump_spans.h"
#include "pipelines/validation/lift_correction.h"
#include "pipelines/validation/validation.h"

namespace softbench {

// The thesis's validation of one bench video (4.1.3, 4.2): measure it, find
// its test points' times (the plan's, the motion's or a pressure log's) and
// score them against the model and the baseline.
struct VideoValidationOptions {
  // Without times in the plan: seconds at rest at the start of the video.
  double rest_s = 1.0;
  // Read only the frames of the tests' windows, seeking between them (the
  // plan must give the times), and, where the windows hold too few still
  // I pictures for the uncertainty's codec term, a few frames around key
  // frames elsewhere (codec_jump_spans.h); the trajectory then holds those
  // frames only.
  bool windows_only = false;
  // Which key frames windows_only also reads, for as many jumps as
  // scoring.min_codec_jumps.
  CodecJumpSpanOptions codec_jump_spans;
  // Register every frame to the bench; false takes the camera to be still
  // (the thesis's method).
  bool register_frames = true;
  // Whether the heads' parallax is taken out of their positions: by
  // default where their measured lifts show they leave the plane.
  LiftCorrectionOptions lift_correction;
  bool progress = true;  // report progress (util/progress.h) while measuring
  ValidationOptions scoring;
  TestPointDetectionOptions detection;

  // The first bad field, named, and what it must be.
  std::optional<std::string> Problem() const;
};

// Where the test points' times come from when the plan's are not used.
struct PressureLogTimes {
  std::string path;                 // the log, for messages
  std::vector<PressureHold> holds;  // PlanPressureHolds
};

// One file a validation read, for the record (summary.json, results.csv).
struct InputFile {
  std::string role;    // one of kInputRoles
  std::string path;    // as given
  std::string sha256;  // 64 lowercase hex digits
};

// Every kind of file a validation can read, in the order reports list them.
inline constexpr const char* kInputRoles[] = {
    "video", "plan", "mechanism", "constants", "pressure_log", "intrinsics"};

// One video's measurement and scores, with the plan's times as used.
struct VideoValidation {
  TestPlan plan;
  VideoMeasurement measurement;
  ValidationResult result;
  // The files this validation read (a built-in mechanism or the thesis's
  // constants are no file and not listed), hashed while the video is
  // measured.
  std::vector<InputFile> inputs;
  // Whether the heads' parallax was taken out, and why.
  LiftCorrectionDecision lift_correction;
};

// Validates the video at `video_path`, opened once for all of it. With a
// pressure log, its holds give the times, aligned by the motion. Throws
// InputError when the video cannot be measured or its test points found.
VideoValidation ValidateVideo(TestPlan plan, const std::string& video_path,
                              const std::optional<PressureLogTimes>& log,
                              const VideoValidationOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_VALIDATION_VALIDATE_VIDEO_H_
