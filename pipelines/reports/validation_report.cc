#include "pipelines/reports/validation_report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <map>
#include <numbers>

#include "pipelines/measurement/snapshots.h"
#include "pipelines/reports/html_report.h"
#include "pipelines/reports/validation_charts.h"
#include "util/version.h"
#include "vision/image_data_uri.h"

namespace softbench {
namespace {

// A mark drawn over a crop, at a sub-pixel position in the frame.
struct CropMark {
  Eigen::Vector2d pixel;
  std::string colour;
  bool cross = false;  // a cross; otherwise a ring
  std::string label;   // tooltip
};

// The crops' JPEG quantiser: FFmpeg's finest, as the crops are looked at
// pixel by pixel (about the size and fidelity of libjpeg's quality 92).
constexpr int kCropJpegQscale = 1;

// One head's crop as SVG: the pixels (JPEG, drawn unsmoothed) in frame
// pixel coordinates, so the marks sit at their exact sub-pixel places.
std::string CropSvg(const HeadCrop& crop, const std::vector<CropMark>& marks,
                    double dot_radius_px) {
  // Pixel i covers [i - 0.5, i + 0.5] (OpenCV's centres are integers).
  const double x0 = crop.origin_px.x() - 0.5, y0 = crop.origin_px.y() - 0.5;
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{} {} {} {}\">"
      "<image href=\"{}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" "
      "style=\"image-rendering:pixelated\"/>",
      x0, y0, crop.bgr.cols, crop.bgr.rows,
      JpegDataUri(crop.bgr, kCropJpegQscale), x0, y0, crop.bgr.cols,
      crop.bgr.rows);
  const double r = 0.35 * dot_radius_px;
  for (const CropMark& mark : marks) {
    if (!mark.pixel.allFinite()) continue;
    const double x = mark.pixel.x(), y = mark.pixel.y();
    const std::string style = fmt::format(
        "stroke=\"{}\" stroke-width=\"1.5\" fill=\"none\" "
        "vector-effect=\"non-scaling-stroke\"",
        mark.colour);
    if (mark.cross) {
      svg += fmt::format(
          "<path d=\"M{} {}L{} {}M{} {}L{} {}\" {}><title>{}</title></path>",
          x - r, y - r, x + r, y + r, x - r, y + r, x + r, y - r, style,
          mark.label);
    } else {
      svg += fmt::format(
          R"(<circle cx="{}" cy="{}" r="{}" {}><title>{}</title></circle>)", x,
          y, r, style, mark.label);
    }
  }
  return svg + "</svg>";
}

// Annotated crops of every test's initial, actuated and final windows (the
// thesis's three frames), a row per test and head.
void AddCrops(const TestPlan& plan, const VideoMeasurement& m,
              const ValidationResult& r, HtmlReport* report) {
  std::map<double, const FrameSnapshot*> by_time;
  for (const FrameSnapshot& s : m.snapshots) by_time[s.requested_s] = &s;
  report->AddParagraph(
      "The frame in the middle of each window (with the times found from "
      "the video, one within 0.1 s of it, kept on the way). Rings: the dots' "
      "sub-pixel centres (cyan) and the head centre in this frame (green); "
      "magenta cross: the initial position (initial window's median); on the "
      "actuated frame, the predicted positions: model blue, baseline orange. "
      "Hover a mark for its name.");
  for (const TestScore& t : r.tests) {
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& score = t.heads[h];
      const Eigen::Vector2d initial_mm =
          m.rest_mm[h] + t.windows[0].median_mm[h];
      const auto pixel_of = [&](const Eigen::Vector2d& displacement_mm) {
        const Eigen::Vector2d plane = initial_mm + displacement_mm;
        return plane.allFinite() ? m.mapping->ToPixel(plane)
                                 : Eigen::Vector2d::Constant(NAN);
      };
      const double dot_radius_px =
          0.5 * plan.markers[h].dot_diameter_mm / m.mm_per_px;
      std::vector<HtmlReport::Figure> figures;
      for (int k = 0; k < 3; ++k) {
        const WindowSummary& w = t.windows[k];
        const auto it = by_time.find(w.middle_s());
        if (it == by_time.end() || it->second->heads[h].bgr.empty()) continue;
        const FrameSnapshot& snapshot = *it->second;
        const FrameSample* sample = FindFrame(m, snapshot.time_s);
        if (sample == nullptr) continue;
        const HeadObservation& obs = sample->heads[h].observation;
        std::vector<CropMark> marks;
        for (const DotObservation& dot : obs.dots) {
          if (dot.found) marks.push_back({dot.pixel, "#0ff", false, "dot"});
        }
        marks.push_back({obs.pixel, "#0f0", false, "head centre"});
        marks.push_back({pixel_of(Eigen::Vector2d::Zero()), "#f0f", true,
                         "initial position"});
        if (k == 1) {
          marks.push_back(
              {pixel_of(score.model_mm), "#4c9bff", true, r.model_name});
          marks.push_back(
              {pixel_of(score.baseline_mm), "#ff9a3c", true, r.baseline_name});
        }
        figures.push_back(
            {CropSvg(snapshot.heads[h], marks, dot_radius_px),
             fmt::format("{} {}, {}: frame {} (t = {:.2f} s)", t.id,
                         plan.mechanism.heads[h].name, kWindowNames[k],
                         snapshot.frame, snapshot.time_s)});
      }
      if (!figures.empty()) report->AddFigures(figures);
    }
  }
}

}  // namespace

std::string FormatMm(double value) { return FormatFixed(value, 4); }

std::string FormatMicrons(double value_mm) { return FormatFixed(value_mm, 5); }

std::string FormatPercent(double value) {
  return std::isfinite(value) ? fmt::format("{:.0f} %", value) : "";
}

namespace {

// The error statistics of the model and the baseline, per head.
void AddSummary(const TestPlan& plan, const ValidationResult& r,
                HtmlReport* report) {
  report->AddHeading("Summary");
  std::vector<std::vector<std::string>> rows;
  for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
    const ErrorStatistics& a = r.model_errors[h];
    const ErrorStatistics& b = r.baseline_errors[h];
    std::vector<double> expanded;
    int significant = 0;
    for (const TestScore& t : r.tests) {
      if (!t.scored()) continue;
      expanded.push_back(2.0 * t.heads[h].budget.TotalMm());
      significant += t.heads[h].model_error_significant ? 1 : 0;
    }
    rows.push_back({plan.mechanism.heads[h].name, std::to_string(a.tests),
                    FormatMm(a.mean_mm), FormatMm(a.max_mm), FormatMm(a.rms_mm),
                    FormatMm(b.mean_mm), FormatMm(b.max_mm), FormatMm(b.rms_mm),
                    FormatPercent(r.improvement_percent[h]),
                    expanded.empty() ? std::string()
                                     : FormatMm(*std::max_element(
                                           expanded.begin(), expanded.end())),
                    fmt::format("{} of {}", significant, expanded.size())});
  }
  report->AddTable(
      {"head", "tests", "model mean [mm]", "model max", "model RMS",
       "baseline mean", "baseline max", "baseline RMS", "improvement",
       "largest U = 2u [mm]", "model errors beyond their U"},
      rows);
  report->AddParagraph(fmt::format(
      "Uncertainty: each measured displacement carries a budget of the "
      "errors this video shows (below, and docs/uncertainty.md): its "
      "standard uncertainty u and expanded uncertainty U = 2u, within which "
      "a displacement's error lies about 98 % of the time. {} A model error "
      "beyond its U is the model's; one within it may be the measurement's. "
      "Hysteresis against the {} mm tolerance: {} exceed it by more than "
      "their U, {} are within it by more than their U, {} cannot tell.",
      std::isfinite(r.largest_expanded_mm)
          ? fmt::format("The largest U is {} mm.",
                        FormatMm(r.largest_expanded_mm))
          : std::string("No test is scored, so there is no U to give."),
      plan.hysteresis_tolerance_mm, r.hysteresis_exceeds, r.hysteresis_within,
      r.hysteresis_cannot_tell));
}

// Each scored displacement's budget: every term's u (both axes in
// quadrature), the total u, U = 2u, and the largest term.
void AddBudgets(const TestPlan& plan, const ValidationResult& r,
                HtmlReport* report) {
  std::vector<std::string> names;
  for (const TestScore& t : r.tests) {
    if (!t.scored()) continue;
    for (const HeadScore& s : t.heads) {
      for (const UncertaintyTerm& term : s.budget.terms) {
        if (std::find(names.begin(), names.end(), term.name) == names.end()) {
          names.push_back(term.name);
        }
      }
    }
  }
  if (names.empty()) return;
  report->AddHeading("Uncertainty budget");
  std::vector<std::string> header = {"test", "head"};
  for (const std::string& name : names) header.push_back(name + " [mm]");
  for (const char* column : {"u [mm]", "U = 2u [mm]", "largest term"}) {
    header.emplace_back(column);
  }
  std::vector<std::vector<std::string>> rows;
  for (const TestScore& t : r.tests) {
    if (!t.scored()) continue;
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const UncertaintyBudget& b = t.heads[h].budget;
      std::vector<std::string> row = {t.id, plan.mechanism.heads[h].name};
      for (const std::string& name : names) {
        const auto term = std::find_if(
            b.terms.begin(), b.terms.end(),
            [&](const UncertaintyTerm& x) { return x.name == name; });
        row.push_back(term == b.terms.end() ? "-"
                                            : FormatMicrons(term->u_mm.norm()));
      }
      row.push_back(FormatMicrons(b.TotalMm()));
      row.push_back(FormatMicrons(2.0 * b.TotalMm()));
      row.push_back(b.Largest());
      rows.push_back(std::move(row));
    }
  }
  report->AddTable(header, rows);
  report->AddParagraph(
      "Each term is the standard uncertainty it adds to the displacement "
      "(dy and dz in quadrature); independent terms add in quadrature. "
      "docs/uncertainty.md says how each is measured from the video.");
}

// "p1 p2 p3" as the plan gives them.
std::string Pressures(const Eigen::VectorXd& pressures) {
  std::vector<std::string> values;
  for (double p : pressures) values.push_back(fmt::format("{:g}", p));
  return fmt::format("{}", fmt::join(values, "  "));
}

void AddTestTable(const TestPlan& plan, const ValidationResult& r,
                  HtmlReport* report) {
  report->AddHeading("Test points");
  std::vector<std::vector<std::string>> rows;
  for (const TestScore& t : r.tests) {
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      std::vector<std::string> frames;
      for (const WindowSummary& w : t.windows) {
        frames.push_back(h < w.head_frames.size()
                             ? std::to_string(w.head_frames[h])
                             : std::string("-"));
      }
      rows.push_back(
          {t.id, Pressures(t.pressures), plan.mechanism.heads[h].name,
           FormatMm(s.measured_mm.x()), FormatMm(s.measured_mm.y()),
           t.scored() ? FormatMicrons(2.0 * s.budget.TotalMm()) : std::string(),
           fmt::format("{}", fmt::join(frames, " / ")),
           FormatMm(s.model_error_mm) +
               (t.scored() ? (s.model_error_significant ? " (beyond U)"
                                                        : " (within U)")
                           : ""),
           FormatMm(s.baseline_error_mm),
           FormatMm(s.hysteresis_mm) + (s.hysteresis_verdict.empty()
                                            ? ""
                                            : ": " + s.hysteresis_verdict),
           t.status + (t.reason.empty() ? "" : ": " + t.reason)});
    }
  }
  for (const TestPoint& t : plan.skipped_tests) {
    rows.push_back({t.id, Pressures(t.pressures), "", "", "", "", "", "", "",
                    "", "skipped (as the plan says)"});
  }
  report->AddTable({"test", "pressures [" + plan.pressure_unit + "]", "head",
                    "measured dy [mm]", "measured dz [mm]", "U = 2u [mm]",
                    "frames initial / actuated / final", "model error [mm]",
                    "baseline error [mm]", "hysteresis [mm]", "status"},
                   rows);
}

void AddRepeats(const TestPlan& plan, const ValidationResult& r,
                HtmlReport* report) {
  report->AddHeading("Repeats");
  std::vector<std::vector<std::string>> rows;
  for (const RepeatAgreement& group : r.repeats) {
    std::vector<std::string> row = {
        fmt::format("{}", fmt::join(group.test_ids, ", "))};
    for (double d : group.max_difference_mm) row.push_back(FormatMm(d));
    rows.push_back(row);
  }
  std::vector<std::string> header = {"tests with the same pressures"};
  for (const Head& head : plan.mechanism.heads) {
    header.push_back(head.name + ": largest difference [mm]");
  }
  report->AddTable(header, rows);
}

// How pixels became millimetres, and how the frames went.
void AddCalibration(const TestPlan& plan, const VideoMeasurement& m,
                    HtmlReport* report) {
  report->AddHeading("Calibration");
  report->AddTable(
      {"item", "value"},
      {{"scale", m.scale_source},
       {"tag", plan.calibration.tag
                   ? fmt::format("{} id {}, {} mm; dots {} mm above it",
                                 plan.calibration.tag->family,
                                 plan.calibration.tag->id,
                                 plan.calibration.tag->size_mm,
                                 plan.calibration.plane_offset_mm)
                   : std::string("none")},
       {"camera tilt to the dot plane (corrected)",
        fmt::format("{:.2f} deg",
                    m.mapping->TiltRad() * 180.0 / std::numbers::pi)},
       {"lens", plan.calibration.intrinsics_path.empty()
                    ? fmt::format("pinhole, {} mm equivalent focal length",
                                  plan.calibration.focal_length_35mm)
                    : "intrinsics " + plan.calibration.intrinsics_path},
       {"mm per pixel at the image centre", fmt::format("{:.5f}", m.mm_per_px)},
       {"distortion check", m.distortion.message},
       {"camera's processing, seen on the tag's border",
        m.camera_processing.Summary()},
       {"rolling shutter, seen in the registration's misfits",
        m.camera_processing.rolling_shutter.Summary()},
       {"registration to the bench", m.registration},
       {"frames not registered",
        m.unregistered_frames == 0
            ? std::string("0")
            : fmt::format("{} ({}: {})", m.unregistered_frames,
                          UnregisteredSpans(m.frames), m.unregistered_reason)},
       {"frames", std::to_string(m.frames.size())},
       {"dot-frames missing", std::to_string(m.missing_dots)},
       {"frames searched in full", std::to_string(m.full_frame_frames)},
       {"same-colour blobs rejected", std::to_string(m.rejected_blobs)}});
  const std::vector<ProcessingEffect>& effects = m.camera_processing.effects;
  if (effects.empty()) return;
  // Each effect named, with why it does not move the figures below.
  std::vector<std::vector<std::string>> rows;
  for (const ProcessingEffect& e : effects) {
    rows.push_back({e.name, e.seen, e.handling});
  }
  report->AddParagraph(
      "The camera processed its images, as the tag's border and the "
      "registration show:");
  report->AddTable({"effect", "seen", "what the measurement does about it"},
                   rows);
}

// What the report was made from: softbench's version and every input file
// with its SHA-256.
void AddInputs(const VideoValidation& v, HtmlReport* report) {
  report->AddHeading("Inputs");
  report->AddParagraph(fmt::format("softbench {}; pressures in {}.",
                                   SoftbenchVersion(), v.plan.pressure_unit));
  std::vector<std::vector<std::string>> rows;
  for (const InputFile& file : v.inputs) {
    rows.push_back({file.role, file.path, file.sha256});
  }
  report->AddTable({"input", "file", "SHA-256"}, rows);
}

}  // namespace

std::string ValidationReportHtml(const VideoValidation& v) {
  const TestPlan& plan = v.plan;
  const VideoMeasurement& m = v.measurement;
  const ValidationResult& r = v.result;
  HtmlReport report("Validation: " + m.video_path);
  report.AddLinks("Files beside this page:",
                  {std::begin(kValidationFiles), std::end(kValidationFiles)});
  report.AddParagraph(fmt::format(
      "{} mechanism, plan {}, {} test points (times from {}); model {} "
      "against the baseline {}.",
      plan.mechanism.name, plan.path, r.tests.size(), r.times_source,
      r.model_name, r.baseline_name));
  for (const std::string& warning : r.warnings) {
    report.AddParagraph("Warning: " + warning);
  }
  AddSummary(plan, r, &report);
  report.AddChart(PositionChart(plan, r));
  report.AddChart(ErrorChart(plan, r));
  // Drawn where lifts were measured (a mapping's plate poses).
  if (const nlohmann::json lift = LiftChart(plan, r);
      !lift["data"]["values"].empty()) {
    report.AddChart(lift);
    report.AddParagraph("The heads' lift and tilt: their parallax " +
                        v.lift_correction.reason + ".");
  }
  report.AddChart(TrajectoryChart(plan, m, r));
  if (m.registers_frames) report.AddChart(CameraMotionChart(m, r));
  report.AddHeading("Frames");
  AddCrops(plan, m, r, &report);
  AddTestTable(plan, r, &report);
  AddBudgets(plan, r, &report);
  report.AddHeading("Hysteresis");
  report.AddParagraph(fmt::format(
      "Tolerance {} mm; flagged: {}. {}", plan.hysteresis_tolerance_mm,
      r.hysteresis_flagged.empty()
          ? std::string("none")
          : fmt::format("{}", fmt::join(r.hysteresis_flagged, ", ")),
      r.hysteresis_cause));
  AddRepeats(plan, r, &report);
  AddCalibration(plan, m, &report);
  AddInputs(v, &report);
  return report.Render();
}

}  // namespace softbench
