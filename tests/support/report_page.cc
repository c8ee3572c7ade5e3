#include "tests/support/report_page.h"

namespace softbench {

std::vector<nlohmann::json> EmbeddedCharts(const std::string& html) {
  // HtmlReport::Render writes each as vegaEmbed('#chartN', SPEC, {actions...
  std::vector<nlohmann::json> charts;
  const std::string open = "vegaEmbed('#chart", close = ", {actions";
  for (size_t at = html.find(open); at != std::string::npos;
       at = html.find(open, at + 1)) {
    const size_t spec = html.find("', ", at) + 3;
    const size_t end = html.find(close, spec);
    // The page escapes "</" as "<\/" inside <script>; JSON reads it back.
    charts.push_back(nlohmann::json::parse(html.substr(spec, end - spec)));
  }
  return charts;
}

std::string ChartTitle(const nlohmann::json& chart) {
  const nlohmann::json& title =
      chart.contains("spec") && !chart.contains("title")
          ? chart["spec"]["title"]
          : chart["title"];
  if (title.is_string()) return title.get<std::string>();
  if (title.is_object() && title.contains("text")) {
    return title["text"].is_string() ? title["text"].get<std::string>()
                                     : title["text"].dump();
  }
  return "";
}

nlohmann::json ChartTitled(const std::string& html, const std::string& title) {
  for (const nlohmann::json& chart : EmbeddedCharts(html)) {
    if (ChartTitle(chart).rfind(title, 0) == 0) return chart;
  }
  return nullptr;
}

}  // namespace softbench
