#include "pipelines/formats/test_plan.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <set>

#include "model/units.h"
#include "pipelines/formats/constants_file.h"
#include "pipelines/formats/dot_colors.h"
#include "pipelines/formats/mechanism_io.h"
#include "util/check.h"
#include "util/input_error.h"
#include "util/text_file.h"
#include "util/yaml_reader.h"

namespace softbench {

// Ten thousand test points are under 1 MB.
constexpr int64_t kMaxPlanBytes = int64_t{4} << 20;
namespace {

namespace fs = std::filesystem;

bool IsBuiltin(const std::string& name) {
  for (const std::string& builtin : BuiltinMechanismNames()) {
    if (name == builtin) return true;
  }
  return false;
}

// A file named in the plan, relative to the plan's folder.
std::string Resolve(const std::string& plan_path, const std::string& name) {
  const fs::path path(name);
  if (path.is_absolute()) return name;
  return (fs::path(plan_path).parent_path() / path).lexically_normal().string();
}

double NonNegative(const YamlReader& reader, const YAML::Node& node,
                   std::string_view key) {
  const double value = reader.Number(node, key);
  if (value < 0.0) reader.Fail(node, key, "must be >= 0");
  return value;
}

double Positive(const YamlReader& reader, const YAML::Node& node,
                std::string_view key) {
  const double value = reader.Number(node, key);
  if (!(value > 0.0)) reader.Fail(node, key, "must be > 0");
  return value;
}

// Fails at `node` when `value` lies outside what a bench has, [lo, hi]:
// "VALUE UNIT is no WHAT; ADVICE" (a typo or a value in another unit).
void CheckPlausible(const YamlReader& reader, const YAML::Node& node,
                    std::string_view key, double value, double lo, double hi,
                    std::string_view unit, std::string_view what,
                    std::string_view advice) {
  if (value < lo || value > hi) {
    reader.Fail(node, key,
                fmt::format("{} {} is no {}; {}", value, unit, what, advice));
  }
}

void ParseCalibration(const YamlReader& reader, const YAML::Node& node,
                      TestPlan* plan) {
  reader.CheckKeys(
      node, "calibration",
      {"tag", "plane_offset_mm", "intrinsics", "focal_length_35mm", "mm_per_px",
       "image_rotation_deg", "scale_from_dots", "distortion_tolerance"});
  CalibrationSpec& c = plan->calibration;
  if (const YAML::Node focal = node["focal_length_35mm"]) {
    c.focal_length_35mm = Positive(reader, focal, "focal_length_35mm");
    // From a fisheye's 8 mm to a long telephoto's 2000 mm (35 mm film
    // equivalent); anything else is a typo or the sensor's real focal length.
    CheckPlausible(reader, focal, "focal_length_35mm", c.focal_length_35mm, 8.0,
                   2000.0, "mm", "camera's 35 mm-equivalent focal length",
                   "give it between 8 and 2000 mm (an iPhone's main camera: "
                   "26)");
  }
  if (const YAML::Node scale = node["mm_per_px"]) {
    c.mm_per_px = Positive(reader, scale, "mm_per_px");
    // A pixel of a bench video spans micrometres to a millimetre or so.
    CheckPlausible(reader, scale, "mm_per_px", *c.mm_per_px, 0.0, 10.0,
                   "mm per pixel", "bench camera's scale (above 10)",
                   "give the scale on the dots' plane (typically 0.01 to 1)");
  }
  if (const YAML::Node rotation = node["image_rotation_deg"]) {
    c.image_rotation_deg = reader.Number(rotation, "image_rotation_deg");
  }
  if (const YAML::Node dots = node["scale_from_dots"]) {
    c.scale_from_dots = reader.Bool(dots, "scale_from_dots");
  }
  if (const YAML::Node tolerance = node["distortion_tolerance"]) {
    c.distortion_tolerance =
        Positive(reader, tolerance, "distortion_tolerance");
  }
  if (const YAML::Node offset = node["plane_offset_mm"]) {
    c.plane_offset_mm = reader.Number(offset, "plane_offset_mm");
  }
  if (const YAML::Node intrinsics = node["intrinsics"]) {
    c.intrinsics_path =
        Resolve(plan->path, reader.String(intrinsics, "intrinsics"));
  }
  if (const YAML::Node tag_node = node["tag"]) {
    reader.CheckKeys(tag_node, "tag", {"family", "id", "size_mm", "center_mm"});
    TagSpec tag;
    if (const YAML::Node family = tag_node["family"]) {
      tag.family = reader.String(family, "family");
      if (tag.family != "tag36h11") {
        reader.Fail(family, "family", "only tag36h11 is supported; print one");
      }
    }
    if (const YAML::Node id = tag_node["id"]) {
      const double value = reader.Number(id, "id");
      if (value < 0 || value >= kTag36h11Codes || value != std::floor(value)) {
        reader.Fail(id, "id",
                    fmt::format("must be a whole number from 0 to {}",
                                kTag36h11Codes - 1));
      }
      tag.id = static_cast<int>(value);
    }
    if (const YAML::Node size = tag_node["size_mm"]) {
      tag.size_mm = Positive(reader, size, "size_mm");
      // The black border's side, as printed: from a sticker to a poster.
      CheckPlausible(reader, size, "size_mm", tag.size_mm, 2.0, 2000.0, "mm",
                     "printed tag's side",
                     "give the black border's side in mm, 2 to 2000 "
                     "(softbench targets prints 50 by default)");
    }
    if (const YAML::Node center = tag_node["center_mm"]) {
      const auto pair = reader.Pair(center, "center_mm");
      tag.center_mm = Eigen::Vector2d(pair[0], pair[1]);
    }
    c.tag = tag;
  }
  const int scales =
      (c.tag ? 1 : 0) + (c.mm_per_px ? 1 : 0) + (c.scale_from_dots ? 1 : 0);
  if (scales > 1) {
    reader.Fail(node, "calibration",
                "give one scale: tag, mm_per_px or scale_from_dots");
  }
}

// A marker's HSV bounds, checked.
std::array<int, 6> ParseHsv(const YamlReader& reader, const YAML::Node& hsv) {
  if (!hsv.IsSequence() || hsv.size() != 6) {
    reader.Fail(hsv, "hsv",
                "must be [h_low, h_high, s_low, s_high, v_low, v_high] "
                "(as softbench tune prints)");
  }
  std::array<int, 6> bounds{};
  for (size_t i = 0; i < 6; ++i) {
    const double v = reader.Number(hsv[i], "hsv");
    if (v != std::floor(v)) reader.Fail(hsv, "hsv", "must be whole numbers");
    bounds[i] = static_cast<int>(v);
  }
  if (auto problem = CheckHsvBounds(bounds)) reader.Fail(hsv, "hsv", *problem);
  return bounds;
}

// The index of the head `node` names in the mechanism.
int HeadIndex(const YamlReader& reader, const YAML::Node& node,
              const Mechanism& mechanism) {
  const std::string name = reader.String(node, "head");
  for (int h = 0; h < mechanism.NumHeads(); ++h) {
    if (mechanism.heads[h].name == name) return h;
  }
  reader.Fail(
      node, "head",
      "'" + name + "' is not a head of mechanism '" + mechanism.name + "'");
}

void ParseMarkers(const YamlReader& reader, const YAML::Node& node,
                  TestPlan* plan) {
  if (!node.IsSequence()) reader.Fail(node, "markers", "must be a list");
  std::vector<bool> seen(plan->mechanism.NumHeads(), false);
  for (const YAML::Node& entry : node) {
    reader.CheckKeys(
        entry, "markers entry",
        {"head", "color", "dots", "dot_diameter_mm", "layout_mm", "hsv"});
    MarkerSpec marker;
    const YAML::Node head = reader.Require(entry, "head");
    const std::string head_name = reader.String(head, "head");
    marker.head = HeadIndex(reader, head, plan->mechanism);
    if (seen[marker.head]) {
      reader.Fail(head, "head", "'" + head_name + "' has markers twice");
    }
    seen[marker.head] = true;
    if (const YAML::Node color = entry["color"]) {
      marker.color = reader.String(color, "color");
      if (FindDotColor(marker.color) == nullptr) {
        reader.Fail(color, "color",
                    "'" + marker.color + "' is not one of " + DotColorNames());
      }
    }
    if (const YAML::Node dots = entry["dots"]) {
      const double value = reader.Number(dots, "dots");
      if (value < 1 || value > 12 || value != std::floor(value)) {
        reader.Fail(dots, "dots", "must be a whole number from 1 to 12");
      }
      marker.dots = static_cast<int>(value);
    }
    if (const YAML::Node diameter = entry["dot_diameter_mm"]) {
      marker.dot_diameter_mm = Positive(reader, diameter, "dot_diameter_mm");
    }
    if (const YAML::Node hsv = entry["hsv"]) marker.hsv = ParseHsv(reader, hsv);
    if (const YAML::Node layout = entry["layout_mm"]) {
      if (!layout.IsSequence() ||
          static_cast<int>(layout.size()) != marker.dots) {
        reader.Fail(
            layout, "layout_mm",
            fmt::format("must list {} [y, z] pairs, one per dot", marker.dots));
      }
      for (const YAML::Node& point : layout) {
        const auto pair = reader.Pair(point, "layout_mm");
        const Eigen::Vector2d p(pair[0], pair[1]);
        // Overlapping dots merge into one blob: no layout can match them.
        for (size_t j = 0; j < marker.layout_mm.size(); ++j) {
          const double gap_mm = (p - marker.layout_mm[j]).norm();
          if (gap_mm < marker.dot_diameter_mm) {
            reader.Fail(
                point, "layout_mm",
                fmt::format("dots {} and {} are {:.2f} mm apart, less than a "
                            "dot's diameter ({} mm): they would overlap; "
                            "give each dot its own place",
                            j + 1, marker.layout_mm.size() + 1, gap_mm,
                            marker.dot_diameter_mm));
          }
        }
        marker.layout_mm.push_back(p);
      }
    }
    plan->markers.push_back(std::move(marker));
  }
  for (int h = 0; h < plan->mechanism.NumHeads(); ++h) {
    if (!seen[h]) {
      reader.Fail(node, "markers",
                  "head '" + plan->mechanism.heads[h].name +
                      "' has no markers; add an entry for it");
    }
  }
  std::sort(
      plan->markers.begin(), plan->markers.end(),
      [](const MarkerSpec& a, const MarkerSpec& b) { return a.head < b.head; });
}

void ParseTests(const YamlReader& reader, const YAML::Node& node,
                TestPlan* plan) {
  if (!node.IsSequence() || node.size() == 0) {
    reader.Fail(node, "tests", "must be a non-empty list");
  }
  const int n = plan->mechanism.NumActuators();
  std::set<std::string, std::less<>> ids;
  for (const YAML::Node& entry : node) {
    reader.CheckKeys(entry, "tests entry",
                     {"id", "pressures", "actuate_s", "release_s",
                      "residual_offset_mm", "skipped"});
    TestPoint test;
    const YAML::Node id = reader.Require(entry, "id");
    test.id = reader.String(id, "id");
    if (!ids.insert(test.id).second) {
      reader.Fail(id, "id",
                  "'" + test.id +
                      "' is used twice; give each test its own id (a test "
                      "done again on the bench gets a new entry, e.g. '" +
                      test.id + "-repeat')");
    }
    const YAML::Node pressures = reader.Require(entry, "pressures");
    if (!pressures.IsSequence() || static_cast<int>(pressures.size()) != n) {
      reader.Fail(pressures, "pressures",
                  fmt::format("mechanism '{}' has {} actuators: give {} "
                              "pressures in {}",
                              plan->mechanism.name, n, n, plan->pressure_unit));
    }
    test.pressures.resize(n);
    for (int k = 0; k < n; ++k) {
      test.pressures[k] = reader.Number(pressures[k], "pressures");
      if (const std::optional<std::string> why = ImplausiblePressure(
              test.pressures[k], plan->mpa_per_unit, plan->pressure_unit)) {
        reader.Fail(pressures[k], "pressures", *why);
      }
    }
    const YAML::Node actuate = entry["actuate_s"];
    const YAML::Node release = entry["release_s"];
    if (actuate.IsDefined() != release.IsDefined()) {
      reader.Fail(entry, "actuate_s",
                  "give both actuate_s and release_s, or neither");
    }
    if (actuate) {
      test.actuate_s = NonNegative(reader, actuate, "actuate_s");
      test.release_s = reader.Number(release, "release_s");
      if (!(*test.release_s > *test.actuate_s)) {
        reader.Fail(release, "release_s", "must be later than actuate_s");
      }
      if (!plan->tests.empty() && plan->tests.back().release_s &&
          !(*test.actuate_s > *plan->tests.back().release_s)) {
        reader.Fail(actuate, "actuate_s",
                    "must be later than the previous test's release_s");
      }
    }
    if (const YAML::Node offset = entry["residual_offset_mm"]) {
      const auto pair = reader.Pair(offset, "residual_offset_mm");
      test.residual_offset_mm = {pair[0], pair[1]};
    }
    const YAML::Node skipped = entry["skipped"];
    if (skipped && reader.Bool(skipped, "skipped")) {
      if (actuate) {
        reader.Fail(actuate, "actuate_s",
                    "a skipped test has no times; remove them or the "
                    "skipped key");
      }
      plan->skipped_tests.push_back(std::move(test));
      continue;
    }
    plan->tests.push_back(std::move(test));
  }
  if (plan->tests.empty()) {
    reader.Fail(node, "tests", "every test is skipped; keep at least one");
  }
  const bool any = std::any_of(plan->tests.begin(), plan->tests.end(),
                               [](const TestPoint& t) { return t.actuate_s; });
  if (any && !plan->HasTimes()) {
    reader.Fail(node, "tests",
                "some tests have times and some do not; give times for all "
                "or for none");
  }
}

void ParseScene(const YamlReader& reader, const YAML::Node& node,
                SceneSpec* scene) {
  reader.CheckKeys(node, "scene",
                   {"settle_time_constant_s", "creep_fraction",
                    "creep_time_constant_s", "head_side_mm", "lead_in_s",
                    "hold_s", "rest_s", "head_lift_mm", "head_tilt_deg"});
  // A bench scene's times are at most a day, its head at most a metre wide,
  // and creep a fraction of the motion: beyond these a value is a typo.
  const auto set = [&](const char* key, double* value, bool positive,
                       double max) {
    if (const YAML::Node v = node[key]) {
      *value =
          positive ? Positive(reader, v, key) : NonNegative(reader, v, key);
      if (*value > max) {
        reader.Fail(v, key, fmt::format("must be at most {}", max));
      }
    }
  };
  set("settle_time_constant_s", &scene->settle_time_constant_s, true, 86400);
  set("creep_fraction", &scene->creep_fraction, false, 1.0);
  set("creep_time_constant_s", &scene->creep_time_constant_s, true, 86400);
  set("head_side_mm", &scene->head_side_mm, false, 1000);
  set("lead_in_s", &scene->lead_in_s, false, 86400);
  set("hold_s", &scene->hold_s, true, 86400);
  set("rest_s", &scene->rest_s, true, 86400);
  // A head a few millimetres up or a few degrees over is no longer a
  // planar mechanism's: its actuators would bend out of their plane.
  set("head_lift_mm", &scene->head_lift_mm, false, 5.0);
  set("head_tilt_deg", &scene->head_tilt_deg, false, 10.0);
}

}  // namespace

std::array<int, 6> MarkerHsvBounds(const MarkerSpec& marker) {
  if (marker.hsv) return *marker.hsv;
  const DotColor* color = FindDotColor(marker.color);
  SOFTBENCH_CHECK(color != nullptr)
      << "marker colour '" << marker.color << "' was not checked when parsed";
  return color->hsv_bounds;
}

bool TestPlan::HasTimes() const {
  return std::all_of(tests.begin(), tests.end(), [](const TestPoint& t) {
    return t.actuate_s.has_value();
  });
}

void CheckWindowsFitTheTimes(const TestPlan& plan) {
  for (size_t i = 0; i < plan.tests.size(); ++i) {
    const TestPoint& test = plan.tests[i];
    const double hold_s = *test.release_s - *test.actuate_s;
    if (hold_s < plan.window_s) {
      throw InputError(fmt::format(
          "{}: test {}: the hold ({:g} s) is shorter than windows.length_s "
          "({:g} s), so its actuated window would reach back to the "
          "actuation; hold longer or shorten the windows",
          plan.path, test.id, hold_s, plan.window_s));
    }
    if (i == 0) continue;
    const double rest_s = *test.actuate_s - *plan.tests[i - 1].release_s;
    if (rest_s < plan.window_s) {
      throw InputError(fmt::format(
          "{}: test {}: actuated only {:g} s after {}'s release, less than "
          "windows.length_s ({:g} s), so its initial window would reach back "
          "to that release; rest longer or shorten the windows",
          plan.path, test.id, rest_s, plan.tests[i - 1].id, plan.window_s));
    }
  }
}

std::vector<Eigen::Vector2d> AttachmentDirections(const Mechanism& mechanism,
                                                  int head) {
  std::vector<Eigen::Vector2d> directions;
  for (const Actuator& actuator : mechanism.actuators) {
    const Eigen::Vector2d axis = mechanism.heads[actuator.head].rest_mm -
                                 mechanism.AnchorRestPosition(actuator);
    if (actuator.head == head) directions.emplace_back(-axis.normalized());
    if (actuator.anchor.kind == AnchorRef::Kind::kHead &&
        actuator.anchor.index == head) {
      directions.push_back(axis.normalized());
    }
  }
  return directions;
}

std::vector<Eigen::Vector2d> DefaultDotLayout(const Mechanism& mechanism,
                                              int head, int dots,
                                              double head_side_mm) {
  // Dots sit toward the triangle's corners, i.e. away from the attachments,
  // at 55 % of the inradius so they clear the edges.
  const double radius = 0.55 * head_side_mm / (2.0 * std::sqrt(3.0));
  const std::vector<Eigen::Vector2d> attachments =
      AttachmentDirections(mechanism, head);
  double start = std::numbers::pi / 2;
  if (attachments.size() == 3) {
    start = std::atan2(-attachments[0].y(), -attachments[0].x());
  }
  std::vector<Eigen::Vector2d> layout;
  for (int i = 0; i < dots; ++i) {
    const double angle = start + 2.0 * std::numbers::pi * i / dots;
    layout.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
  }
  if (dots == 1) layout[0].setZero();
  return layout;
}

namespace {

// The mechanism (built-in or a file beside the plan), the constants file and
// the variant.
void ParseModel(const YamlReader& reader, const YAML::Node& root,
                const std::string& path, TestPlan* plan_ptr) {
  TestPlan& plan = *plan_ptr;
  const YAML::Node mechanism = reader.Require(root, "mechanism");
  plan.mechanism_name = reader.String(mechanism, "mechanism");
  if (!IsBuiltin(plan.mechanism_name)) {
    plan.mechanism_path = Resolve(path, plan.mechanism_name);
  }
  try {
    plan.mechanism =
        LoadMechanism(plan.mechanism_path.empty() ? plan.mechanism_name
                                                  : plan.mechanism_path);
  } catch (const InputError& e) {
    reader.Fail(mechanism, "mechanism", e.what());
  }
  ConstantsFile constants;
  if (const YAML::Node file = root["constants"]) {
    plan.constants_path = Resolve(path, reader.String(file, "constants"));
    try {
      constants = LoadConstantsFile(plan.constants_path);
    } catch (const InputError& e) {
      reader.Fail(file, "constants", e.what());
    }
  }
  std::string variant = constants.variant.value_or("small-angle");
  if (const YAML::Node v = root["variant"])
    variant = reader.String(v, "variant");
  const std::optional<ForceModel> model =
      ForceModelFromVariantName(variant, constants.constants);
  if (!model) {
    reader.Fail(
        root["variant"], "variant",
        "'" + variant + "' is not a variant; use " + ModelVariantNames());
  }
  plan.force_model = *model;
  plan.range = constants.range;
}

void ParsePressureUnit(const YamlReader& reader, const YAML::Node& root,
                       TestPlan* plan_ptr) {
  TestPlan& plan = *plan_ptr;
  const YAML::Node unit = reader.Require(root, "pressure_unit");
  plan.pressure_unit = reader.String(unit, "pressure_unit");
  if (const PressureUnit* found = FindPressureUnit(plan.pressure_unit)) {
    plan.pressure_unit = found->name;  // "kPa" is written back as kpa
    plan.mpa_per_unit = found->mpa_per_unit;
  } else {
    reader.Fail(unit, "pressure_unit", "must be " + PressureUnitNames());
  }
}

// The plan's markers, or the thesis's: red dots on the delta head, another
// colour per further head; each layout defaulted from the head's shape.
void ParseOrDefaultMarkers(const YamlReader& reader, const YAML::Node& root,
                           TestPlan* plan_ptr) {
  TestPlan& plan = *plan_ptr;
  if (const YAML::Node markers = root["markers"]) {
    ParseMarkers(reader, markers, &plan);
  } else {
    for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
      MarkerSpec marker;
      marker.head = h;
      const auto colors = DotColors();
      marker.color = colors[h % colors.size()].name;
      plan.markers.push_back(marker);
    }
  }
  for (MarkerSpec& marker : plan.markers) {
    if (marker.layout_mm.empty()) {
      marker.layout_mm = DefaultDotLayout(plan.mechanism, marker.head,
                                          marker.dots, plan.scene.head_side_mm);
    }
  }
}

}  // namespace

TestPlan ParseTestPlan(std::string_view yaml, const std::string& path) {
  const YamlReader reader(path);
  const YAML::Node root = reader.Parse(yaml);
  if (!root.IsMap()) throw InputError(path + ": a test plan is a YAML map");
  reader.CheckKeys(
      root, "test plan",
      {"mechanism", "constants", "variant", "pressure_unit", "calibration",
       "markers", "windows", "hysteresis_tolerance_mm", "tests", "scene"});
  TestPlan plan;
  plan.path = path;
  ParseModel(reader, root, path, &plan);
  ParsePressureUnit(reader, root, &plan);
  if (const YAML::Node calibration = root["calibration"]) {
    ParseCalibration(reader, calibration, &plan);
  }
  if (const YAML::Node scene = root["scene"])
    ParseScene(reader, scene, &plan.scene);
  if (plan.scene.head_side_mm == 0.0) {
    plan.scene.head_side_mm = plan.mechanism.NumHeads() == 1 ? 40.0 : 32.0;
  }
  ParseOrDefaultMarkers(reader, root, &plan);
  if (const YAML::Node windows = root["windows"]) {
    reader.CheckKeys(windows, "windows", {"length_s"});
    if (const YAML::Node length = windows["length_s"]) {
      plan.window_s = Positive(reader, length, "length_s");
    }
  }
  if (const YAML::Node tolerance = root["hysteresis_tolerance_mm"]) {
    plan.hysteresis_tolerance_mm =
        Positive(reader, tolerance, "hysteresis_tolerance_mm");
  }
  ParseTests(reader, reader.Require(root, "tests"), &plan);
  return plan;
}

TestPlan LoadTestPlan(const std::string& path) {
  return ParseTestPlan(ReadTextFile(path, "test plan", kMaxPlanBytes), path);
}

}  // namespace softbench
