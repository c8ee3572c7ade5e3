#ifndef SOFTBENCH_PIPELINES_REPORTS_WEB_ASSETS_H_
#define SOFTBENCH_PIPELINES_REPORTS_WEB_ASSETS_H_

#include <string_view>

namespace softbench {

// The pages' own CSS and JavaScript, written as files in report/ (linted
// there, editable in a browser) and embedded at build time
// (web_assets.cc.in), so a report stays one self-contained file.
extern const std::string_view kReportStyle;    // report/report.css
extern const std::string_view kTunePageStyle;  // report/tune_page.css
// report/tune_core.js (HSV and blobs as the C++ computes them), then
// report/tune_page.js (the sliders).
extern const std::string_view kTuneCoreScript;
extern const std::string_view kTunePageScript;

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_WEB_ASSETS_H_
