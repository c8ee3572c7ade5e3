#ifndef SOFTBENCH_PIPELINES_REPORTS_HTML_REPORT_H_
#define SOFTBENCH_PIPELINES_REPORTS_HTML_REPORT_H_

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace softbench {

// The Vega-Lite version AddChart's specifications are written for (the
// vega-lite npm package scripts/bootstrap.sh installs).
inline constexpr char kVegaLiteSchema[] =
    "https://vega.github.io/schema/vega-lite/v6.json";

// A self-contained HTML report: headings, text, tables and Vega-Lite charts,
// with Vega, Vega-Lite and vega-embed inlined from the npm packages that
// scripts/bootstrap.sh installs (report/node_modules), so the page works
// offline and the report directory can be mailed as is. Every chart has a
// menu to save it as SVG or PNG (for a paper); the page reads on a phone's
// width and prints without the menus.
class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void AddHeading(const std::string& text);
  // `text` is escaped; no markup.
  void AddParagraph(const std::string& text);
  // A line with a link (relative `href`, escaped).
  void AddLink(const std::string& text, const std::string& href);
  // One line: `label` then a link to each relative `hrefs` (its name shown).
  void AddLinks(const std::string& label,
                const std::vector<std::string>& hrefs);
  void AddTable(const std::vector<std::string>& header,
                const std::vector<std::vector<std::string>>& rows);
  // A Vega-Lite specification (data inlined in it).
  void AddChart(const nlohmann::json& vega_lite);
  // A row of pictures, each an SVG element the caller built (images in it
  // inlined with JpegDataUri) above its caption (escaped).
  struct Figure {
    std::string svg;
    std::string caption;
  };
  void AddFigures(const std::vector<Figure>& figures);

  // The page; throws InputError when it has charts and the plotting
  // libraries are missing (a page without charts needs none).
  std::string Render() const;

 private:
  std::string title_;
  std::string body_;
  std::vector<nlohmann::json> charts_;
};

// `text` made safe as HTML text or an attribute value.
std::string HtmlEscape(const std::string& text);

// A number with `decimals` decimals for a report's tables and CSVs; NaN and
// inf (no value: a statistic of nothing) become `missing`, never "nan".
std::string FormatFixed(double value, int decimals,
                        std::string_view missing = "");

// A number for a report's JSON: NaN and inf (not representable) become null.
inline nlohmann::json JsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json();
}

// Where the plotting libraries are: $SOFTBENCH_REPORT_ASSETS, else the
// source tree's report/node_modules.
std::string ReportAssetsDirectory();

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_HTML_REPORT_H_
