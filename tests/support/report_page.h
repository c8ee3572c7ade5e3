#ifndef SOFTBENCH_TESTS_SUPPORT_REPORT_PAGE_H_
#define SOFTBENCH_TESTS_SUPPORT_REPORT_PAGE_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace softbench {

// The Vega-Lite specifications a report page embeds, in page order.
std::vector<nlohmann::json> EmbeddedCharts(const std::string& html);

// A chart's title (a string, or a title object's text).
std::string ChartTitle(const nlohmann::json& chart);

// The embedded chart whose title starts with `title`; null when there is
// none. Tests find charts by title, so adding a chart moves none of them.
nlohmann::json ChartTitled(const std::string& html, const std::string& title);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_REPORT_PAGE_H_
