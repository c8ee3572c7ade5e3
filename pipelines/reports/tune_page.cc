#include "pipelines/reports/tune_page.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "pipelines/reports/html_report.h"
#include "pipelines/reports/web_assets.h"
#include "vision/image_data_uri.h"

namespace softbench {

std::string TunePageHtml(const cv::Mat& bgr, const std::string& source,
                         double time_s, const std::vector<TunedColor>& colors,
                         const SegmentationOptions& segmentation) {
  nlohmann::json described = nlohmann::json::array();
  std::string controls;
  const char* labels[] = {"hue low",         "hue high",  "saturation low",
                          "saturation high", "value low", "value high"};
  const char* keys[] = {"h_lo", "h_hi", "s_lo", "s_hi", "v_lo", "v_hi"};
  for (const TunedColor& color : colors) {
    // The mask's tint: magenta over any colour, easy to tell from the dots.
    described.push_back({{"name", color.name},
                         {"radius", color.found ? color.dot_radius_px : 0.0},
                         {"tint", {255, 0, 255}}});
    controls += fmt::format("<fieldset><legend>{}</legend>\n", color.name);
    for (int k = 0; k < 6; ++k) {
      controls += fmt::format(
          "<label>{0}<input type=\"range\" id=\"{1}-{2}\" min=\"0\" "
          "max=\"{3}\" value=\"{4}\"><span id=\"{1}-{2}-value\">{4}</span>"
          "</label>\n",
          labels[k], color.name, keys[k], k < 2 ? 179 : 255, color.bounds[k]);
    }
    controls += fmt::format(
        "<p class=\"status\"><span id=\"status-{0}\"></span> (<span "
        "id=\"dots-{0}\"></span> dots, <span id=\"pixels-{0}\"></span> "
        "pixels in range){1}</p></fieldset>\n",
        color.name,
        color.found
            ? ""
            : "; tune found none in its range: " + HtmlEscape(color.why_not));
  }
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, "
      "initial-scale=1\">\n<title>softbench tune: {0}</title>\n"
      "<style>{1}</style></head>\n<body>\n<h1>Colour thresholds: {0} at t = "
      "{2:.3f} s</h1>\n<p>Move the sliders until each colour's dots, and "
      "nothing else, are magenta; a green ring marks each blob of a dot's "
      "size. Then paste the YAML into the plan.</p>\n"
      "<div class=\"layout\"><div class=\"controls\">\n{3}"
      "<label><span>mask only</span><input type=\"checkbox\" "
      "id=\"mask-only\"><span></span></label>\n"
      "<pre id=\"yaml\"></pre></div>\n"
      "<div class=\"picture\"><canvas id=\"view\"></canvas></div></div>\n"
      "<script>const COLORS = {4}; const MIN_AREA = {5}; const MAX_AREA = "
      "{6}; const PICTURE = '{7}';</script>\n<script>{8}</script>\n"
      "<script>{9}</script>\n"
      "</body></html>\n",
      HtmlEscape(source), kTunePageStyle, time_s, controls, described.dump(),
      segmentation.min_area_fraction, segmentation.max_area_fraction,
      PngDataUri(bgr), kTuneCoreScript, kTunePageScript);
}

}  // namespace softbench
