#ifndef SOFTBENCH_PIPELINES_COMMANDS_TUNE_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_TUNE_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace softbench {

// `softbench tune`: one frame's colour segmentation made visible, and HSV
// bounds learned from its dots (replaces MATLAB's Color Thresholder app).
struct TuneCommandOptions {
  std::string video_path;
  double at_s = 0.0;
  std::string color = "red";
  std::string hsv;             // "h_lo,h_hi,s_lo,s_hi,v_lo,v_hi" to try
  double dot_radius_px = 0.0;  // 0: estimated from the blobs
  std::string output_dir = ".";
};

// Adds the command's flags to `command`, bound to `options`.
void AddTuneCommand(CLI::App* command, TuneCommandOptions* options);
int RunTune(const TuneCommandOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_TUNE_COMMAND_H_
