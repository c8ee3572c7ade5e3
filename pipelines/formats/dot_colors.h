#ifndef SOFTBENCH_PIPELINES_FORMATS_DOT_COLORS_H_
#define SOFTBENCH_PIPELINES_FORMATS_DOT_COLORS_H_

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace softbench {

// A colour of printed dot a plan may name (docs/file-formats.md, "Test plan").
// This is the one list: plan parsing, `tune`, the renderer, help texts and
// every message about colours use it.
struct DotColor {
  std::string_view name;
  // Built-in HSV bounds [h_low, h_high, s_low, s_high, v_low, v_high] in
  // OpenCV units (hue 0-180; h_low > h_high wraps through 0). Printed dots
  // are saturated; the resin heads, bellows and table are not (saturation
  // < 70 in the thesis's footage and our renderings), so the saturation
  // floor does most of the separating and hue names the colour.
  std::array<int, 6> hsv_bounds;
  // The ink as the renderer paints it, 8-bit BGR.
  std::array<int, 3> ink_bgr;
};

// In the order plans without markers give them to heads (thesis: red dots on
// the delta's head).
std::span<const DotColor> DotColors();

// The colour called `name`, or null.
const DotColor* FindDotColor(std::string_view name);

// Why HSV bounds [h_low, h_high, s_low, s_high, v_low, v_high] are not valid
// (OpenCV units), or nullopt.
std::optional<std::string> CheckHsvBounds(const std::array<int, 6>& bounds);

// "red, green, blue, yellow or magenta", for help texts and errors.
std::string DotColorNames();

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_DOT_COLORS_H_
