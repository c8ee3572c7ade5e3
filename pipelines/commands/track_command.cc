#include "pipelines/commands/track_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "pipelines/commands/common_flags.h"
#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/reports/validation_files.h"
#include "util/atomic_file.h"
#include "util/input_error.h"

namespace softbench {

void AddTrackCommand(CLI::App* c, TrackCommandOptions* options) {
  c->add_option("video", options->video_path, "bench video")->required();
  AddPlanOption(c, &options->plan_path);
  AddOutOption(c, &options->output_path, "trajectory CSV to write")->required();
  AddRestOption(c, &options->rest_s);
  AddNoRegistrationFlag(c, &options->no_registration);
  c->add_flag("--lift-correction", options->lift_correction,
              "take the parallax of each head's measured lift and tilt out "
              "of its position (off by default: track has no test points "
              "over which to tell a lift from the dots' noise, and from the "
              "dots alone one frame's lift is known to about 0.1 mm at "
              "1080p; validate decides from its tests; "
              "docs/measurement.md)");
  c->add_flag("--full-frame", options->full_frame,
              "search the whole image in every frame (slow; for checks)");
}

int RunTrack(const TrackCommandOptions& options, std::ostream& out) {
  const TestPlan plan = LoadTestPlan(options.plan_path);
  CheckOutputFile(options.output_path, "--out");
  CheckOutputsSpareInputs(
      {{"the video", options.video_path}, {"--plan", options.plan_path}},
      {{"--out", options.output_path}}, {});
  VideoMeasurementOptions measure;
  if (!(options.rest_s > 0.0)) throw InputError("--rest-s: must be > 0");
  measure.rest_s = options.rest_s;
  measure.tracker.full_frame_every_frame = options.full_frame;
  measure.register_frames = !options.no_registration;
  measure.correct_lift = options.lift_correction;
  measure.progress = !options.quiet;
  const VideoMeasurement m = MeasureVideo(plan, options.video_path, measure);
  WriteFileAtomically(options.output_path, TrajectoryCsv(plan, m));
  out << fmt::format(
      "measured {} frames of {}: scale from {} ({:.5f} mm/px at the image "
      "centre); {} dot-frames missing, {} frames searched in full, {} "
      "same-colour blobs rejected; trajectory in {}\n",
      m.frames.size(), options.video_path, m.scale_source, m.mm_per_px,
      m.missing_dots, m.full_frame_frames, m.rejected_blobs,
      options.output_path);
  if (m.camera_processing.measured) {
    out << "camera's processing, seen on the tag's border: "
        << m.camera_processing.Summary() << "\n";
  }
  // Each frame's positions keep a rolling shutter's shear (only windows'
  // medians average it out), so a trajectory's reader is told of it.
  if (m.camera_processing.rolling_shutter.measured) {
    out << "rolling shutter: " << m.camera_processing.rolling_shutter.Summary()
        << "\n";
  }
  if (m.distortion.performed) {
    if (m.distortion.warn) {
      spdlog::warn("{}", m.distortion.message);
    } else {
      out << "distortion check: " << m.distortion.message << "\n";
    }
  }
  return 0;
}

}  // namespace softbench
