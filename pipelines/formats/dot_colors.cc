#include "pipelines/formats/dot_colors.h"

#include <vector>

#include "util/join_names.h"

namespace softbench {

std::span<const DotColor> DotColors() {
  static constexpr DotColor kColors[] = {
      {"red", {170, 10, 100, 255, 50, 255}, {40, 40, 200}},
      {"green", {40, 85, 90, 255, 40, 255}, {70, 160, 40}},
      {"blue", {95, 130, 100, 255, 40, 255}, {190, 90, 30}},
      {"yellow", {18, 35, 100, 255, 60, 255}, {40, 200, 225}},
      {"magenta", {140, 168, 90, 255, 40, 255}, {170, 50, 190}}};
  return kColors;
}

const DotColor* FindDotColor(std::string_view name) {
  for (const DotColor& color : DotColors()) {
    if (color.name == name) return &color;
  }
  return nullptr;
}

std::optional<std::string> CheckHsvBounds(const std::array<int, 6>& bounds) {
  const auto [hue_low, hue_high, saturation_low, saturation_high, value_low,
              value_high] = bounds;
  if (hue_low < 0 || hue_low > 179 || hue_high < 0 || hue_high > 179) {
    return "hue bounds must be 0..179 (OpenCV units; low > high wraps "
           "through 180)";
  }
  if (saturation_low < 0 || saturation_high > 255 ||
      saturation_low > saturation_high) {
    return "saturation bounds must satisfy 0 <= low <= high <= 255";
  }
  if (value_low < 0 || value_high > 255 || value_low > value_high) {
    return "value bounds must satisfy 0 <= low <= high <= 255";
  }
  return std::nullopt;
}

std::string DotColorNames() {
  std::vector<std::string_view> names;
  for (const DotColor& color : DotColors()) names.push_back(color.name);
  return JoinNames(names);
}

}  // namespace softbench
