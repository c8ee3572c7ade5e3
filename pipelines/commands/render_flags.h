#ifndef SOFTBENCH_PIPELINES_COMMANDS_RENDER_FLAGS_H_
#define SOFTBENCH_PIPELINES_COMMANDS_RENDER_FLAGS_H_

#include <opencv2/core.hpp>
#include <string>

#include "pipelines/synthetic/bench_conditions.h"

namespace softbench {

// Resolution names: "720p", "1080p", "4k" or "WxH"; throws InputError.
cv::Size ParseResolution(const std::string& text);

// Parses "T:DX,DY" or "T:DX,DY,ROLL_DEG" (seconds, pixels, degrees) as given
// to `render --camera-bump`; throws InputError naming the option.
CameraBump ParseCameraBump(const std::string& text);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_RENDER_FLAGS_H_
