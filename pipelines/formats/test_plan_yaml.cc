// Writing a test plan back as YAML (TestPlanToYaml): what `render` writes
// beside its video with the times it used.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <functional>

#include "pipelines/formats/test_plan.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

// A file name relative to the directory a written plan goes to.
using RelativeTo = std::function<std::string(const std::string&)>;

// The calibration section; keys beyond the defaults only when set, so
// rendered plans stay short.
void EmitCalibration(const TestPlan& plan, const RelativeTo& relative,
                     YAML::Emitter* emitter) {
  YAML::Emitter& out = *emitter;
  out << YAML::Key << "calibration" << YAML::Value << YAML::BeginMap;
  const CalibrationSpec& c = plan.calibration;
  out << YAML::Key << "plane_offset_mm" << YAML::Value << c.plane_offset_mm;
  if (!c.intrinsics_path.empty()) {
    out << YAML::Key << "intrinsics" << YAML::Value
        << relative(c.intrinsics_path);
  }
  if (c.focal_length_35mm != CalibrationSpec().focal_length_35mm) {
    out << YAML::Key << "focal_length_35mm" << YAML::Value
        << c.focal_length_35mm;
  }
  if (c.mm_per_px)
    out << YAML::Key << "mm_per_px" << YAML::Value << *c.mm_per_px;
  if (c.scale_from_dots) {
    out << YAML::Key << "scale_from_dots" << YAML::Value << true;
  }
  if (c.mm_per_px || c.scale_from_dots) {
    out << YAML::Key << "image_rotation_deg" << YAML::Value
        << c.image_rotation_deg;
  }
  if (c.distortion_tolerance != CalibrationSpec().distortion_tolerance) {
    out << YAML::Key << "distortion_tolerance" << YAML::Value
        << c.distortion_tolerance;
  }
  if (plan.calibration.tag) {
    const TagSpec& tag = *plan.calibration.tag;
    out << YAML::Key << "tag" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "family" << YAML::Value << tag.family;
    out << YAML::Key << "id" << YAML::Value << tag.id;
    out << YAML::Key << "size_mm" << YAML::Value << tag.size_mm;
    if (tag.center_mm) {
      out << YAML::Key << "center_mm" << YAML::Value << YAML::Flow
          << YAML::BeginSeq << tag.center_mm->x() << tag.center_mm->y()
          << YAML::EndSeq;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

void EmitMarkers(const TestPlan& plan, YAML::Emitter* emitter) {
  YAML::Emitter& out = *emitter;
  out << YAML::Key << "markers" << YAML::Value << YAML::BeginSeq;
  for (const MarkerSpec& m : plan.markers) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "head" << YAML::Value
        << plan.mechanism.heads[m.head].name;
    out << YAML::Key << "color" << YAML::Value << m.color;
    out << YAML::Key << "dots" << YAML::Value << m.dots;
    out << YAML::Key << "dot_diameter_mm" << YAML::Value << m.dot_diameter_mm;
    out << YAML::Key << "layout_mm" << YAML::Value << YAML::BeginSeq;
    for (const Eigen::Vector2d& p : m.layout_mm) {
      out << YAML::Flow << YAML::BeginSeq << p.x() << p.y() << YAML::EndSeq;
    }
    out << YAML::EndSeq;
    if (m.hsv) {
      out << YAML::Key << "hsv" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (int v : *m.hsv) out << v;
      out << YAML::EndSeq;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

void EmitScene(const TestPlan& plan, YAML::Emitter* emitter) {
  YAML::Emitter& out = *emitter;
  const SceneSpec& s = plan.scene;
  out << YAML::Key << "scene" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "settle_time_constant_s" << YAML::Value
      << s.settle_time_constant_s;
  out << YAML::Key << "creep_fraction" << YAML::Value << s.creep_fraction;
  out << YAML::Key << "creep_time_constant_s" << YAML::Value
      << s.creep_time_constant_s;
  out << YAML::Key << "head_side_mm" << YAML::Value << s.head_side_mm;
  out << YAML::Key << "lead_in_s" << YAML::Value << s.lead_in_s;
  out << YAML::Key << "hold_s" << YAML::Value << s.hold_s;
  out << YAML::Key << "rest_s" << YAML::Value << s.rest_s;
  if (s.head_lift_mm > 0.0 || s.head_tilt_deg > 0.0) {
    out << YAML::Key << "head_lift_mm" << YAML::Value << s.head_lift_mm;
    out << YAML::Key << "head_tilt_deg" << YAML::Value << s.head_tilt_deg;
  }
  out << YAML::EndMap;
}

// One test entry: id and pressures, then what else it has.
void EmitTest(const TestPoint& t, bool skipped, YAML::Emitter* emitter) {
  YAML::Emitter& out = *emitter;
  out << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "id" << YAML::Value << t.id;
  out << YAML::Key << "pressures" << YAML::Value << YAML::Flow
      << YAML::BeginSeq;
  for (double p : t.pressures) out << p;
  out << YAML::EndSeq;
  if (skipped) out << YAML::Key << "skipped" << YAML::Value << true;
  if (t.actuate_s) {
    out << YAML::Key << "actuate_s" << YAML::Value << *t.actuate_s;
    out << YAML::Key << "release_s" << YAML::Value << *t.release_s;
  }
  if (!t.residual_offset_mm.isZero()) {
    out << YAML::Key << "residual_offset_mm" << YAML::Value << YAML::Flow
        << YAML::BeginSeq << t.residual_offset_mm.x()
        << t.residual_offset_mm.y() << YAML::EndSeq;
  }
  out << YAML::EndMap;
}

void EmitTests(const TestPlan& plan, YAML::Emitter* emitter) {
  YAML::Emitter& out = *emitter;
  out << YAML::Key << "tests" << YAML::Value << YAML::BeginSeq;
  for (const TestPoint& t : plan.skipped_tests) EmitTest(t, true, emitter);
  for (const TestPoint& t : plan.tests) EmitTest(t, false, emitter);
  out << YAML::EndSeq;
}

}  // namespace

std::string TestPlanToYaml(const TestPlan& plan,
                           const std::string& output_dir) {
  const RelativeTo relative = [&](const std::string& file) {
    // A path the file system cannot relate (too long, say) stays absolute:
    // still right, only longer.
    std::error_code error;
    const fs::path absolute = fs::absolute(file, error);
    if (error) return file;
    const fs::path base = fs::absolute(output_dir, error);
    if (error) return absolute.string();
    const fs::path relative = fs::relative(absolute, base, error);
    return error || relative.empty() ? absolute.string() : relative.string();
  };
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << YAML::BeginMap;
  out << YAML::Key << "mechanism" << YAML::Value
      << (plan.mechanism_path.empty() ? plan.mechanism_name
                                      : relative(plan.mechanism_path));
  if (!plan.constants_path.empty()) {
    out << YAML::Key << "constants" << YAML::Value
        << relative(plan.constants_path);
  }
  out << YAML::Key << "variant" << YAML::Value
      << std::string(VariantName(plan.force_model));
  out << YAML::Key << "pressure_unit" << YAML::Value << plan.pressure_unit;
  EmitCalibration(plan, relative, &out);
  EmitMarkers(plan, &out);
  out << YAML::Key << "windows" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "length_s" << YAML::Value << plan.window_s
      << YAML::EndMap;
  out << YAML::Key << "hysteresis_tolerance_mm" << YAML::Value
      << plan.hysteresis_tolerance_mm;
  EmitScene(plan, &out);
  EmitTests(plan, &out);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace softbench
