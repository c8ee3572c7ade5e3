#ifndef SOFTBENCH_PIPELINES_COMMANDS_TUNE_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_TUNE_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace softbench {

// `softbench tune`: one frame's (or photo's) colour segmentation made
// visible, HSV bounds learned from its dots, and a page with sliders to set
// them by eye (replaces MATLAB's Color Thresholder app).
struct TuneCommandOptions {
  std::string source_path;  // a video, or a photo (PNG, JPEG)
  double at_s = 0.0;
  std::string color = "red";   // one or more, comma-separated
  std::string hsv;             // "h_lo,h_hi,s_lo,s_hi,v_lo,v_hi" to try
  double dot_radius_px = 0.0;  // 0: estimated from the blobs
  std::string output_dir = ".";
};

// Adds the command's flags to `command`, bound to `options`.
void AddTuneCommand(CLI::App* command, TuneCommandOptions* options);
int RunTune(const TuneCommandOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_TUNE_COMMAND_H_
