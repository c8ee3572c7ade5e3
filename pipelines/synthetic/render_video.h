#ifndef SOFTBENCH_PIPELINES_SYNTHETIC_RENDER_VIDEO_H_
#define SOFTBENCH_PIPELINES_SYNTHETIC_RENDER_VIDEO_H_

#include <cstdint>
#include <optional>
#include <string>

#include "pipelines/formats/test_plan.h"
#include "pipelines/synthetic/bench_conditions.h"
#include "pipelines/synthetic/scene_renderer.h"
#include "pipelines/synthetic/temporal_denoiser.h"
#include "vision/video_writer.h"

namespace softbench {

// iPhones' timestamp clock [ticks per second], the clock of a rendered
// variable frame rate.
inline constexpr int kPhoneClockHz = 600;

// Bench footage of a test plan with exact ground truth (docs/rendering.md).
struct RenderVideoOptions {
  // The scene and the camera: intrinsics (the frame size), distance, tilt,
  // noise, motion blur, seed. Its exposure is cut to one frame interval.
  RenderOptions scene;
  // What a phone on a tripod adds: drift, tremor, bumps, exposure and white
  // balance wandering.
  BenchConditionsOptions conditions;
  // The video as the phone writes it: codec, quality, bit depth, chroma,
  // range, HDR encoding, rotation and frame rate. The stored picture is the
  // scene's frame turned by the rotation.
  VideoWriterOptions writer;
  // Variable frame rate: each frame's time moves by up to this fraction of
  // the frame interval (0-0.9), on kPhoneClockHz; 0: constant.
  double vfr_jitter = 0.0;
  // A rolling shutter: the time from reading the sensor's first line to its
  // last [s] (a phone: 10-30 ms), so each line sees the camera where it was
  // then and tremor shears the frame. The frame's time is its middle line's.
  // Lines are the stored video's rows (the upright picture's columns in a
  // portrait video). 0: every line read at once; at most one frame interval.
  double readout_s = 0.0;
  // A phone's temporal noise reduction on each frame's codes against the
  // previous frame (issue 28); none by default.
  TemporalDenoiseOptions temporal_denoise;
  bool progress = true;  // report progress (util/progress.h)

  // The first bad field, named, and what it must be.
  std::optional<std::string> Problem() const;
};

struct RenderedVideo {
  TestPlan plan;  // with the times used (AssignTimes)
  int64_t frames = 0;
  double duration_s = 0.0;
  // Per frame: the heads' true displacements and pixels, the camera's
  // motion and the brightness (docs/file-formats.md, "Truth").
  std::string truth_csv;
};

// Renders the plan to `video_path`, written through a temporary file renamed
// into place at the end (a failure leaves no half-written video). Throws
// InputError when the plan's equilibria cannot be found or the video cannot
// be written.
RenderedVideo RenderVideo(TestPlan plan, const std::string& video_path,
                          const RenderVideoOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_SYNTHETIC_RENDER_VIDEO_H_
