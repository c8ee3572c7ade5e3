#ifndef SOFTBENCH_PIPELINES_COMMANDS_TRACK_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_TRACK_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace softbench {

// `softbench track`: a bench video to the per-frame head trajectory.
struct TrackCommandOptions {
  std::string plan_path;
  std::string video_path;
  std::string output_path;       // trajectory CSV
  double rest_s = 1.0;           // rest window when the plan has no times
  bool full_frame = false;       // search the whole image in every frame
  bool no_registration = false;  // take the camera to be still
  bool lift_correction = false;  // take out the heads' parallax
  bool quiet = false;
};

// Adds the command's flags to `command`, bound to `options`.
void AddTrackCommand(CLI::App* command, TrackCommandOptions* options);
int RunTrack(const TrackCommandOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_TRACK_COMMAND_H_
