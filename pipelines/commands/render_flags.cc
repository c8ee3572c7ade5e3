#include "pipelines/commands/render_flags.h"

#include <vector>

#include "pipelines/commands/model_flags.h"
#include "util/input_error.h"

namespace softbench {

cv::Size ParseResolution(const std::string& text) {
  if (text == "720p") return {1280, 720};
  if (text == "1080p") return {1920, 1080};
  if (text == "4k") return {3840, 2160};
  int w = 0, h = 0;
  char x = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &w, &x, &h) == 3 && x == 'x' &&
      w >= 16 && h >= 16 && w <= 8192 && h <= 8192 && w % 2 == 0 &&
      h % 2 == 0) {
    return {w, h};
  }
  throw InputError("--resolution: '" + text +
                   "' is not 720p, 1080p, 4k or WxH with even sides from "
                   "16 to 8192 pixels");
}

CameraBump ParseCameraBump(const std::string& text) {
  const size_t colon = text.find(':');
  const auto fail = [&] {
    return InputError("--camera-bump: '" + text +
                      "' is not T:DX,DY or T:DX,DY,ROLL_DEG (seconds, "
                      "pixels, degrees), e.g. 4.5:2,0.5,0.05");
  };
  if (colon == std::string::npos) throw fail();
  CameraBump bump;
  const std::vector<double> time =
      ParseNumberList(text.substr(0, colon), "--camera-bump");
  const std::vector<double> rest =
      ParseNumberList(text.substr(colon + 1), "--camera-bump");
  if (time.size() != 1 || (rest.size() != 2 && rest.size() != 3)) throw fail();
  bump.time_s = time[0];
  bump.shift_px = {rest[0], rest[1]};
  if (rest.size() == 3) bump.roll_deg = rest[2];
  return bump;
}

void ApplyPhoneProcessing(const PhoneProcessingFlags& flags,
                          RenderOptions* scene) {
  const bool isp = flags.isp;
  scene->lens_blur_px = flags.lens_blur_px.value_or(isp ? 0.6 : 0.0);
  scene->tone_curve = flags.tone_curve.value_or(isp ? 0.6 : 0.0);
  scene->local_tone = flags.local_tone.value_or(isp ? 0.3 : 0.0);
  if (!flags.sharpen.empty()) {
    const std::vector<double> s = ParseNumberList(flags.sharpen, "--sharpen");
    if (s.size() != 2) throw InputError("--sharpen: give radius_px,amount");
    scene->sharpen_radius_px = s[0];
    scene->sharpen_amount = s[1];
  } else if (isp) {
    scene->sharpen_radius_px = 1.0;
    scene->sharpen_amount = 0.8;
  }
  if (!flags.bayer.empty()) {
    const std::optional<Demosaic> demosaic = ParseDemosaic(flags.bayer);
    if (!demosaic) {
      throw InputError("--bayer: '" + flags.bayer +
                       "' is not a demosaic; give bilinear or edge-aware");
    }
    scene->sensor.demosaic = *demosaic;
  } else if (isp) {
    scene->sensor.demosaic = Demosaic::kEdgeAware;
  }
  scene->sensor.full_well_e = flags.sensor_full_well_e.value_or(
      isp && scene->sensor.demosaic != Demosaic::kNone ? 6000.0 : 0.0);
  scene->sensor.read_noise_e = flags.sensor_read_noise_e.value_or(
      scene->sensor.full_well_e > 0.0 ? 2.0 : 0.0);
}

TemporalDenoiseOptions TemporalDenoiseFromFlags(
    const PhoneProcessingFlags& flags) {
  TemporalDenoiseOptions options;
  options.strength = flags.temporal_denoise.value_or(flags.isp ? 0.5 : 0.0);
  if (auto problem = options.Problem()) {
    throw InputError("--temporal-denoise: " + *problem);
  }
  return options;
}

}  // namespace softbench
