#include "pipelines/reports/html_report.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>

#include "pipelines/reports/web_assets.h"
#include "util/input_error.h"
#include "util/text_file.h"

namespace softbench {

// The chart library is a few hundred kilobytes.
constexpr int64_t kMaxAssetBytes = int64_t{16} << 20;
namespace {

std::string Escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Text made safe inside <script>: every `pattern` (which would end the
// element early) gets its slash escaped, which JavaScript strings, regular
// expressions and JSON all read back as a plain slash.
std::string EscapeSlashAfter(std::string text, std::string_view pattern) {
  for (size_t at = 0; (at = text.find(pattern, at)) != std::string::npos;
       at += 2) {
    text.insert(at + 1, "\\");
  }
  return text;
}

}  // namespace

std::string HtmlEscape(const std::string& text) { return Escape(text); }

std::string FormatFixed(double value, int decimals, std::string_view missing) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, decimals)
                              : std::string(missing);
}

std::string ReportAssetsDirectory() {
  if (const char* assets = std::getenv("SOFTBENCH_REPORT_ASSETS")) {
    return assets;
  }
  return SOFTBENCH_REPORT_ASSETS_DIR;
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::AddHeading(const std::string& text) {
  body_ += "<h2>" + Escape(text) + "</h2>\n";
}

void HtmlReport::AddParagraph(const std::string& text) {
  body_ += "<p>" + Escape(text) + "</p>\n";
}

void HtmlReport::AddLink(const std::string& text, const std::string& href) {
  body_ += "<p><a href=\"" + Escape(href) + "\">" + Escape(text) + "</a></p>\n";
}

void HtmlReport::AddLinks(const std::string& label,
                          const std::vector<std::string>& hrefs) {
  body_ += "<p>" + Escape(label);
  for (size_t i = 0; i < hrefs.size(); ++i) {
    body_ += std::string(i == 0 ? " " : " · ") + "<a href=\"" +
             Escape(hrefs[i]) + "\">" + Escape(hrefs[i]) + "</a>";
  }
  body_ += "</p>\n";
}

void HtmlReport::AddTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table><tr>";
  for (const std::string& cell : header)
    body_ += "<th>" + Escape(cell) + "</th>";
  body_ += "</tr>\n";
  for (const std::vector<std::string>& row : rows) {
    body_ += "<tr>";
    for (const std::string& cell : row)
      body_ += "<td>" + Escape(cell) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::AddChart(const nlohmann::json& vega_lite) {
  body_ += fmt::format("<div class=\"chart\" id=\"chart{}\"></div>\n",
                       charts_.size());
  charts_.push_back(vega_lite);
}

void HtmlReport::AddFigures(const std::vector<Figure>& figures) {
  body_ += "<div class=\"figures\">\n";
  for (const Figure& figure : figures) {
    body_ += "<figure>" + figure.svg + "<figcaption>" + Escape(figure.caption) +
             "</figcaption></figure>\n";
  }
  body_ += "</div>\n";
}

std::string HtmlReport::Render() const {
  // The plotting libraries and the charts, only for a page that has some.
  std::string scripts;
  if (!charts_.empty()) {
    const std::filesystem::path assets(ReportAssetsDirectory());
    for (const char* library :
         {"vega/build/vega.min.js", "vega-lite/build/vega-lite.min.js",
          "vega-embed/build/vega-embed.min.js"}) {
      const std::filesystem::path path = assets / library;
      std::error_code error;
      if (!std::filesystem::is_regular_file(path, error)) {
        throw InstallationError(
            path.string() +
            ": the report's plotting library is missing; run "
            "scripts/bootstrap.sh (it installs report/ with npm) "
            "or set SOFTBENCH_REPORT_ASSETS");
      }
      scripts += "<script>" +
                 EscapeSlashAfter(ReadTextFile(path.string(), "report asset",
                                               kMaxAssetBytes),
                                  "</script") +
                 "</script>\n";
    }
  }
  std::string embed;
  for (size_t i = 0; i < charts_.size(); ++i) {
    embed += fmt::format(
        "<script>vegaEmbed('#chart{}', {}, {{actions: {{export: true, "
        "source: false, compiled: false, editor: false}}, renderer: "
        "'svg'}});</script>\n",
        i,
        EscapeSlashAfter(
            charts_[i].dump(-1, ' ', false,
                            nlohmann::json::error_handler_t::replace),
            "</"));
  }
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, "
      "initial-scale=1\">\n"
      "<title>{0}</title>\n<style>{1}</style>\n{2}</head>\n<body>\n"
      "<h1>{0}</h1>\n{3}{4}</body></html>\n",
      Escape(title_), kReportStyle, scripts, body_, embed);
}

}  // namespace softbench
