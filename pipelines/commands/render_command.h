#ifndef SOFTBENCH_PIPELINES_COMMANDS_RENDER_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_RENDER_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "pipelines/commands/render_flags.h"
#include "pipelines/synthetic/bench_conditions.h"
#include "pipelines/synthetic/scene_renderer.h"

namespace softbench {

// `softbench render`: bench footage of a test plan with exact ground truth.
struct RenderCommandOptions {
  std::string plan_path;
  std::string output_path;  // video (.mp4)
  std::string truth_path;   // per-frame truth CSV
  std::string
      plan_out_path;  // the plan with the times used; default beside the video
  std::string resolution = "1080p";  // 720p, 1080p, 4k or WxH
  std::string codec = "h264";
  int crf = 20;
  double bitrate_mbps = 0.0;  // > 0: instead of the CRF
  double keyframe_interval_s = 2.0;
  std::string preset = "medium";
  double fps = 30.0;
  double focal_35mm = 52.0;
  double focal_px = 0.0;            // overrides focal_35mm when > 0
  std::string principal_point;      // "cx,cy" in pixels; default: the centre
  std::string tilt_deg;             // "x,y"
  std::string distortion;           // "k1,k2,p1,p2,k3"
  PhoneProcessingFlags processing;  // --isp, --lens-blur, --bayer, ...
  bool no_motion_blur = false;
  bool no_ring = false;
  // What a phone's video is like: bits, chroma, range, HDR transfer, the
  // rotation a portrait video stores, and the jitter of a variable frame
  // rate (a fraction of the frame interval).
  int bit_depth = 8;
  std::string chroma = "4:2:0";
  bool full_range = false;
  std::string hdr;  // "", "hlg" or "pq"
  int rotation_deg = 0;
  double vfr_jitter = 0.0;
  double rolling_shutter_ms = 0.0;  // first line to last; 0: global shutter
  // Camera motion and exposure drift (bench_conditions.h).
  std::string camera_drift_px;            // "dx,dy" over the whole video
  std::vector<std::string> camera_bumps;  // "t:dx,dy[,roll_deg]" each
  BenchConditionsOptions conditions;
  bool quiet = false;
  RenderOptions render;  // distance, noise, distractors, seed
};

// Adds the command's flags to `command`, bound to `options`.
void AddRenderCommand(CLI::App* command, RenderCommandOptions* options);
int RunRender(RenderCommandOptions options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_RENDER_COMMAND_H_
