#ifndef SOFTBENCH_PIPELINES_COMMANDS_RENDER_FLAGS_H_
#define SOFTBENCH_PIPELINES_COMMANDS_RENDER_FLAGS_H_

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "pipelines/synthetic/bench_conditions.h"
#include "pipelines/synthetic/scene_renderer.h"
#include "pipelines/synthetic/temporal_denoiser.h"

namespace softbench {

// Resolution names: "720p", "1080p", "4k" or "WxH"; throws InputError.
cv::Size ParseResolution(const std::string& text);

// Parses "T:DX,DY" or "T:DX,DY,ROLL_DEG" (seconds, pixels, degrees) as given
// to `render --camera-bump`; throws InputError naming the option.
CameraBump ParseCameraBump(const std::string& text);

// A phone's processing as `render` is asked for it (docs/rendering.md): each
// stage's own flag, unset unless given, and --isp, a typical phone's
// pipeline for every stage not given.
struct PhoneProcessingFlags {
  bool isp = false;
  std::optional<double> lens_blur_px;
  std::optional<double> tone_curve;
  std::optional<double> local_tone;
  std::optional<double> temporal_denoise;
  std::string sharpen;  // "radius_px,amount"
  std::string bayer;    // "bilinear" or "edge-aware"
  std::optional<double> sensor_full_well_e;
  std::optional<double> sensor_read_noise_e;
};

// Sets `scene`'s lens blur, sensor, tone curves and sharpening: a stage's flag
// wins over --isp's preset, which wins over none. Throws InputError naming
// the flag for a malformed value; ranges are RenderOptions::Problem's.
void ApplyPhoneProcessing(const PhoneProcessingFlags& flags,
                          RenderOptions* scene);

// The temporal noise reduction of --temporal-denoise, or --isp's.
TemporalDenoiseOptions TemporalDenoiseFromFlags(
    const PhoneProcessingFlags& flags);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_RENDER_FLAGS_H_
