#include "pipelines/reports/validation_files.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "pipelines/reports/html_report.h"
#include "pipelines/reports/validation_report.h"
#include "util/csv.h"
#include "util/input_error.h"
#include "util/version.h"

namespace softbench {

using nlohmann::json;

std::string TrajectoryCsv(const TestPlan& plan,
                          const VideoMeasurement& measurement) {
  std::string csv =
      "frame,time_s,head,u_px,v_px,y_mm,z_mm,sigma_mm,u_y_mm,u_z_mm,"
      "dots_found,dots,rotation_rad,lift_mm,tilt_y_rad,tilt_z_rad,"
      "binary_y_mm,binary_z_mm,full_frame,"
      "registered,camera_dx_px,camera_dy_px,camera_roll_rad,note\n";
  // Each head's standard uncertainty in a frame (the terms that need no
  // windows), where its position is measured.
  const CodecLevel codec = MeasureCodecLevel(measurement);
  std::vector<Eigen::Vector2d> u;
  for (size_t h = 0; h < plan.markers.size(); ++h) {
    u.push_back(FrameUncertaintyMm(measurement, codec, static_cast<int>(h)));
  }
  for (const FrameSample& f : measurement.frames) {
    for (size_t h = 0; h < f.heads.size(); ++h) {
      const HeadSample& s = f.heads[h];
      const HeadObservation& o = s.observation;
      const bool located = s.displacement_mm.allFinite();
      csv += fmt::format(
          "{},{:.6f},{},{:.4f},{:.4f},{:.5f},{:.5f},{:.5f},{},{},{},{},{:.6f},"
          "{:.4f},{:.6f},{:.6f},{:.5f},{:.5f},{},{},{:.4f},{:.4f},{:.7f},{}\n",
          f.frame, f.time_s,
          CsvField(plan.mechanism.heads[plan.markers[h].head].name),
          o.pixel.x(), o.pixel.y(), s.displacement_mm.x(),
          s.displacement_mm.y(), o.sigma_mm,
          located ? FormatMicrons(u[h].x()) : "nan",
          located ? FormatMicrons(u[h].y()) : "nan", o.dots_found,
          o.dots.size(), o.rotation_rad, s.lift_mm, s.tilt_rad.x(),
          s.tilt_rad.y(), s.binary_displacement_mm.x(),
          s.binary_displacement_mm.y(), o.full_frame ? 1 : 0,
          f.registered ? 1 : 0, f.camera_shift_px.x(), f.camera_shift_px.y(),
          f.camera_roll_rad, CsvField(o.note));
    }
  }
  return csv;
}

namespace {

// The cells every results.csv row ends with: version, pressure unit, and
// each role's file name and SHA-256 (empty for a role not used).
std::string ProvenanceHeader() {
  std::string header = ",softbench_version,pressure_unit";
  for (const char* role : kInputRoles) {
    header += fmt::format(",{0}_file,{0}_sha256", role);
  }
  return header;
}

std::string ProvenanceCells(const VideoValidation& v) {
  std::string cells =
      "," + CsvField(SoftbenchVersion()) + "," + CsvField(v.plan.pressure_unit);
  for (const char* role : kInputRoles) {
    const auto file =
        std::find_if(v.inputs.begin(), v.inputs.end(),
                     [&](const InputFile& f) { return f.role == role; });
    cells +=
        file == v.inputs.end()
            ? ",,"
            : "," +
                  CsvField(
                      std::filesystem::path(file->path).filename().string()) +
                  "," + file->sha256;
  }
  return cells;
}

// u_dy_mm, u_dz_mm, u_mm, u_largest_term, model_error_significant,
// hysteresis_u_mm and hysteresis_verdict where the test is scored, to a
// hundredth of a micrometre (uncertainties are a few micrometres).
std::string UncertaintyCells(const TestScore& t, const HeadScore& s) {
  if (!t.scored()) return ",,,,,,";
  return FormatMicrons(s.budget.u_mm.x()) + "," +
         FormatMicrons(s.budget.u_mm.y()) + "," +
         FormatMicrons(s.budget.TotalMm()) + "," +
         CsvField(s.budget.Largest()) + "," +
         (s.model_error_significant ? "1" : "0") + "," +
         FormatMicrons(s.hysteresis_budget.TotalMm()) + "," +
         CsvField(s.hysteresis_verdict);
}

// lift_mm, u_lift_mm, final_lift_mm, u_final_lift_mm and lift_shift_mm
// where the test is measured (issue 27).
std::string LiftCells(const TestScore& t, const HeadScore& s) {
  if (!t.measured) return ",,,,";
  return FormatMm(s.lift_mm) + "," + FormatMm(s.u_lift_mm) + "," +
         FormatMm(s.final_lift_mm) + "," + FormatMm(s.u_final_lift_mm) + "," +
         FormatMicrons(s.lift_shift_mm);
}

}  // namespace

std::string ResultsCsv(const VideoValidation& v) {
  const TestPlan& plan = v.plan;
  const ValidationResult& r = v.result;
  const std::string provenance = ProvenanceCells(v);
  std::string csv = "test_id,head";
  for (int k = 1; k <= plan.mechanism.NumActuators(); ++k) {
    csv += fmt::format(",p{}_{}", k, plan.pressure_unit);
  }
  csv +=
      ",initial_y_mm,initial_z_mm,actuated_y_mm,actuated_z_mm,final_y_mm,"
      "final_z_mm,measured_dy_mm,measured_dz_mm,model_dy_mm,model_dz_mm,"
      "model_error_mm,baseline_dy_mm,baseline_dz_mm,baseline_error_mm,"
      "hysteresis_mm,hysteresis_ok,in_range,within_reach,status,reason,"
      "u_dy_mm,u_dz_mm,u_mm,u_largest_term,model_error_significant,"
      "hysteresis_u_mm,hysteresis_verdict,"
      "lift_mm,u_lift_mm,final_lift_mm,u_final_lift_mm,lift_shift_mm,"
      "frames_initial,frames_actuated,frames_final" +
      ProvenanceHeader() + "\n";
  for (const TestScore& t : r.tests) {
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      csv += CsvField(t.id) + "," + CsvField(plan.mechanism.heads[h].name);
      for (int k = 0; k < t.pressures.size(); ++k) {
        csv += fmt::format(",{:g}", t.pressures[k]);
      }
      for (int k = 0; k < 3; ++k) {
        csv += "," + FormatMm(t.windows[k].median_mm[h].x()) + "," +
               FormatMm(t.windows[k].median_mm[h].y());
      }
      for (const Eigen::Vector2d& v : {s.measured_mm, s.model_mm}) {
        csv += "," + FormatMm(v.x()) + "," + FormatMm(v.y());
      }
      // Errors and hysteresis only where scored: a test that did not move
      // as its entry predicts has no error against that entry.
      const auto scored = [&](double value) {
        return t.scored() ? FormatMm(value) : std::string();
      };
      csv += "," + scored(s.model_error_mm) + "," +
             FormatMm(s.baseline_mm.x()) + "," + FormatMm(s.baseline_mm.y()) +
             "," + scored(s.baseline_error_mm) + "," + scored(s.hysteresis_mm) +
             "," +
             (t.scored() && s.hysteresis_judged ? (s.hysteresis_ok ? "1" : "0")
                                                : "") +
             "," + (t.outside_range.empty() ? "1" : "0") + "," +
             (t.beyond_reach.empty() ? "1" : "0") + "," + CsvField(t.status) +
             "," + CsvField(t.reason) + "," + UncertaintyCells(t, s) + "," +
             LiftCells(t, s);
      for (const WindowSummary& w : t.windows) {
        csv +=
            "," + (h < w.head_frames.size() ? std::to_string(w.head_frames[h])
                                            : std::string());
      }
      csv += provenance + "\n";
    }
  }
  // Tests the plan says the bench skipped: their pressures, nothing measured.
  for (const TestPoint& t : plan.skipped_tests) {
    for (const Head& head : plan.mechanism.heads) {
      csv += CsvField(t.id) + "," + CsvField(head.name);
      for (double p : t.pressures) csv += fmt::format(",{:g}", p);
      csv += std::string(18, ',') +  // 18 empty cells
             ",skipped,skipped on the bench (the plan says so),,,,,,,,,,,,,,," +
             provenance + "\n";
    }
  }
  return csv;
}

namespace {

// A budget's total and terms.
json BudgetJson(const UncertaintyBudget& budget) {
  json terms = json::array();
  for (const UncertaintyTerm& term : budget.terms) {
    terms.push_back({{"term", term.name},
                     {"u_dy_mm", JsonNumber(term.u_mm.x())},
                     {"u_dz_mm", JsonNumber(term.u_mm.y())}});
  }
  return {{"u_dy_mm", JsonNumber(budget.u_mm.x())},
          {"u_dz_mm", JsonNumber(budget.u_mm.y())},
          {"u_mm", JsonNumber(budget.TotalMm())},
          {"expanded_mm", JsonNumber(2.0 * budget.TotalMm())},
          {"largest_term", budget.Largest()},
          {"terms", terms}};
}

// A rolling shutter as the registration measured it: the readouts along
// the rows and the columns with their standard errors [ms].
json RollingShutterJson(const RollingShutter& r) {
  if (!r.measured) return {{"measured", false}, {"why_not", r.why_not}};
  return {{"measured", true},
          {"frames", r.frames},
          {"seen", r.seen},
          {"lines", r.by_rows ? "rows" : "columns"},
          {"rows_readout_ms", JsonNumber(1e3 * r.rows_readout_s)},
          {"rows_standard_error_ms", JsonNumber(1e3 * r.rows_standard_error_s)},
          {"columns_readout_ms", JsonNumber(1e3 * r.columns_readout_s)},
          {"columns_standard_error_ms",
           JsonNumber(1e3 * r.columns_standard_error_s)},
          {"shear_rms_px", JsonNumber(r.shear_rms_px)}};
}

// What the footage showed of the camera's processing: the tag border's
// signs (each the median over the tag's frames, with its unit), the
// rolling shutter, and the effects named.
json CameraProcessingJson(const CameraProcessing& p) {
  json effects = json::array();
  for (const ProcessingEffect& e : p.effects) {
    effects.push_back(
        {{"effect", e.name}, {"seen", e.seen}, {"handling", e.handling}});
  }
  json out = {{"measured", p.measured}};
  if (p.measured) {
    out["frames"] = p.frames;
    out["edge_shift_px"] = JsonNumber(p.signs.edge_shift_px);
    out["halo_percent"] = JsonNumber(100.0 * p.signs.halo);
    out["white_ratio_percent"] = JsonNumber(100.0 * p.signs.white_ratio);
    out["dots_weighed_in"] = p.sharpened ? "codes" : "linear light";
    out["tag_cell_px"] = JsonNumber(p.tag_cell_px);
    out["tag_scale_at_risk"] = p.tag_scale_at_risk;
    if (p.tag_model) {
      const TagModelFit& f = *p.tag_model;
      json fit = {{"found", f.found}};
      if (f.found) {
        fit["scale_change_percent"] =
            JsonNumber(100.0 * p.tag_model_scale_change);
        fit["lens_blur_px"] = JsonNumber(f.lens_blur_px);
        fit["pixel_filter"] = JsonNumber(f.pixel_filter);
        fit["tone_curve"] = JsonNumber(f.tone_curve);
        fit["sharpen_radius_px"] = JsonNumber(f.sharpen_radius_px);
        fit["sharpen_amount"] = JsonNumber(f.sharpen_amount);
        fit["rms_levels"] = JsonNumber(f.rms_levels);
        fit["pixels"] = f.pixels;
        fit["iterations"] = f.iterations;
      } else {
        fit["why_not"] = f.why_not;
      }
      out["tag_model"] = fit;
    }
  } else {
    out["why_not"] = p.why_not;
  }
  out["rolling_shutter"] = RollingShutterJson(p.rolling_shutter);
  out["effects"] = effects;
  return out;
}

// One test's windows and, where measured, its heads' uncertainty budgets.
json TestJson(const TestPlan& plan, const TestScore& t) {
  json test = {{"id", t.id},
               {"status", t.status},
               {"reason", t.reason},
               {"within_reach", t.beyond_reach.empty()}};
  if (!t.beyond_reach.empty()) test["beyond_reach"] = t.beyond_reach;
  for (int k = 0; k < 3; ++k) {
    const WindowSummary& w = t.windows[k];
    json window = {{"start_s", w.start_s},
                   {"end_s", w.end_s},
                   {"frames", w.frames},
                   {"unregistered_frames", w.unregistered_frames},
                   {"camera_shift_px",
                    {JsonNumber(w.camera_shift_px.x()),
                     JsonNumber(w.camera_shift_px.y())}},
                   {"camera_motion_px", w.camera_motion_px}};
    for (size_t h = 0; h < w.median_mm.size(); ++h) {
      window["heads"].push_back(
          {{"frames", w.head_frames[h]},
           {"median_mm",
            {JsonNumber(w.median_mm[h].x()), JsonNumber(w.median_mm[h].y())}},
           {"spread_mm",
            {JsonNumber(w.spread_mm[h].x()), JsonNumber(w.spread_mm[h].y())}}});
    }
    test["windows"][kWindowNames[k]] = window;
  }
  if (t.measured) {
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      test["uncertainty"].push_back(
          {{"head", plan.mechanism.heads[h].name},
           {"displacement", BudgetJson(s.budget)},
           {"hysteresis", BudgetJson(s.hysteresis_budget)},
           {"model_error_significant", s.model_error_significant},
           {"hysteresis_verdict", s.hysteresis_verdict},
           {"lift",
            {{"lift_mm", JsonNumber(s.lift_mm)},
             {"u_lift_mm", JsonNumber(s.u_lift_mm)},
             {"final_lift_mm", JsonNumber(s.final_lift_mm)},
             {"u_final_lift_mm", JsonNumber(s.u_final_lift_mm)},
             {"lift_shift_mm", JsonNumber(s.lift_shift_mm)}}}});
    }
  }
  return test;
}

}  // namespace

json SummaryJson(const VideoValidation& v) {
  const TestPlan& plan = v.plan;
  const VideoMeasurement& m = v.measurement;
  const ValidationResult& r = v.result;
  json root;
  root["softbench_version"] = SoftbenchVersion();
  root["video"] = m.video_path;
  root["plan"] = plan.path;
  root["mechanism"] = plan.mechanism.name;
  root["pressure_unit"] = plan.pressure_unit;
  root["inputs"] = json::array();
  for (const InputFile& file : v.inputs) {
    root["inputs"].push_back(
        {{"role", file.role},
         {"file", std::filesystem::path(file.path).filename().string()},
         {"path", file.path},
         {"sha256", file.sha256}});
  }
  root["model"] = r.model_name;
  root["times_source"] = r.times_source;
  root["baseline"] = r.baseline_name;
  root["calibration"] = {
      {"scale_source", m.scale_source},
      {"mm_per_px", m.mm_per_px},
      {"tilt_deg", m.mapping->TiltRad() * 180.0 / std::numbers::pi},
      {"distortion_check", m.distortion.message},
      {"distortion_warning", m.distortion.warn}};
  if (m.distortion.performed) {
    const DistortionCheck& d = m.distortion;
    json layout = {
        {"spacing_over_layout_percent", 100.0 * (d.median_ratio - 1.0)},
        {"range_percent", 100.0 * (d.max_ratio - d.min_ratio)},
        {"tolerance_percent", 100.0 * d.tolerance},
        {"shape_misfit_percent", nullptr},
        {"shape_head", nullptr},
        {"implied_plane_offset_mm", nullptr}};
    if (d.shape_head >= 0) {
      layout["shape_misfit_percent"] = 100.0 * d.shape_misfit;
      layout["shape_head"] = plan.mechanism.heads[d.shape_head].name;
    }
    if (std::isfinite(d.implied_plane_offset_mm)) {
      layout["implied_plane_offset_mm"] = d.implied_plane_offset_mm;
    }
    root["calibration"]["layout_check"] = std::move(layout);
  }
  root["camera_processing"] = CameraProcessingJson(m.camera_processing);
  root["registration"] = {{"method", m.registration},
                          {"unregistered_frames", m.unregistered_frames},
                          {"first_reason", m.unregistered_reason},
                          {"camera_moved_windows", r.camera_moved_windows}};
  root["damaged_frames"] = {{"decoded_with_errors", m.damaged_frames},
                            {"never_decoded", m.lost_frame_times_s.size()}};
  root["frames"] = m.frames.size();
  root["every_frame"] = m.every_frame;
  root["lift_corrected"] = m.lift_corrected;
  root["lift_correction"] = {
      {"mode", LiftCorrectionModeName(v.lift_correction.mode)},
      {"lifts", v.lift_correction.lifts},
      {"chi_squared", JsonNumber(v.lift_correction.chi_squared)},
      {"p_value", JsonNumber(v.lift_correction.p_value)},
      {"reason", v.lift_correction.reason}};
  root["missing_dots"] = m.missing_dots;
  root["full_frame_frames"] = m.full_frame_frames;
  for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
    const auto stats = [](const ErrorStatistics& s) {
      return json{{"tests", s.tests},
                  {"mean_mm", JsonNumber(s.mean_mm)},
                  {"max_mm", JsonNumber(s.max_mm)},
                  {"rms_mm", JsonNumber(s.rms_mm)}};
    };
    root["heads"].push_back(
        {{"head", plan.mechanism.heads[h].name},
         {"model_error", stats(r.model_errors[h])},
         {"baseline_error", stats(r.baseline_errors[h])},
         {"improvement_percent", JsonNumber(r.improvement_percent[h])}});
  }
  for (const RepeatAgreement& group : r.repeats) {
    root["repeats"].push_back({{"tests", group.test_ids},
                               {"max_difference_mm", group.max_difference_mm}});
  }
  root["hysteresis"] = {{"tolerance_mm", plan.hysteresis_tolerance_mm},
                        {"flagged", r.hysteresis_flagged},
                        {"shared_cause", r.hysteresis_cause},
                        {"exceeds_tolerance", r.hysteresis_exceeds},
                        {"within_tolerance", r.hysteresis_within},
                        {"cannot_tell", r.hysteresis_cannot_tell}};
  root["largest_expanded_uncertainty_mm"] = JsonNumber(r.largest_expanded_mm);
  root["warnings"] = r.warnings;
  for (const TestPoint& t : plan.skipped_tests) {
    root["skipped_tests"].push_back(t.id);
  }
  for (const TestScore& t : r.tests) root["tests"].push_back(TestJson(plan, t));
  return root;
}

void WriteValidationFiles(const VideoValidation& v,
                          const std::string& directory_name) {
  const std::filesystem::path directory(directory_name);
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error) {
    throw InputError(directory_name + ": cannot create the report folder (" +
                     error.message() + ")");
  }
  WriteFileAtomically((directory / "report.html").string(),
                      ValidationReportHtml(v));
  WriteFileAtomically((directory / "results.csv").string(), ResultsCsv(v));
  WriteFileAtomically(
      (directory / "summary.json").string(),
      SummaryJson(v).dump(2, ' ', false, json::error_handler_t::replace) +
          "\n");
  WriteFileAtomically((directory / "trajectory.csv").string(),
                      TrajectoryCsv(v.plan, v.measurement));
}

void WriteValidationIndex(const std::vector<VideoValidation>& videos,
                          const std::vector<std::string>& names,
                          const AtomicDirectory& report) {
  HtmlReport index("Validation of " + std::to_string(videos.size()) +
                   " videos");
  std::string csv =
      "video,report,head,tests_measured,model_mean_mm,model_max_mm,"
      "baseline_mean_mm,improvement_percent,hysteresis_flagged\n";
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < videos.size(); ++i) {
    const VideoValidation& v = videos[i];
    const ValidationResult& r = v.result;
    index.AddLink(v.measurement.video_path, names[i] + "/report.html");
    for (int h = 0; h < v.plan.mechanism.NumHeads(); ++h) {
      const std::string flagged =
          fmt::format("{}", fmt::join(r.hysteresis_flagged, " "));
      csv += fmt::format(
          "{},{},{},{},{},{},{},{},{}\n", CsvField(v.measurement.video_path),
          CsvField(names[i] + "/report.html"),
          CsvField(v.plan.mechanism.heads[h].name), r.model_errors[h].tests,
          FormatFixed(r.model_errors[h].mean_mm, 5),
          FormatFixed(r.model_errors[h].max_mm, 5),
          FormatFixed(r.baseline_errors[h].mean_mm, 5),
          FormatFixed(r.improvement_percent[h], 1), CsvField(flagged));
      rows.push_back({names[i], v.plan.mechanism.heads[h].name,
                      std::to_string(r.model_errors[h].tests),
                      FormatMm(r.model_errors[h].mean_mm),
                      FormatMm(r.model_errors[h].max_mm),
                      FormatMm(r.baseline_errors[h].mean_mm),
                      FormatPercent(r.improvement_percent[h]),
                      flagged.empty() ? "none" : flagged});
    }
  }
  index.AddTable({"video", "head", "tests", "model mean [mm]", "model max",
                  "baseline mean", "improvement", "hysteresis flagged"},
                 rows);
  WriteFileAtomically(report.File("index.html"), index.Render());
  WriteFileAtomically(report.File("index.csv"), csv);
}

}  // namespace softbench
