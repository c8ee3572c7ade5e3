#include "pipelines/formats/test_plan.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "util/input_error.h"
#include "util/text_file.h"

namespace softbench {
namespace {

std::string PlanError(const std::string& yaml) {
  return InputErrorOf([&] { ParseTestPlan(yaml, "plan.yaml"); });
}

constexpr char kBase[] = "mechanism: floating\npressure_unit: psi\ntests:\n";

TEST(TestPlan, DefaultsGiveEveryHeadAColourAndACentredLayout) {
  const TestPlan plan = ParseTestPlan(
      std::string(kBase) + "  - {id: t1, pressures: [1, 2, 3, 4, 5]}\n",
      "p.yaml");
  ASSERT_EQ(plan.markers.size(), 2u);
  EXPECT_EQ(plan.markers[0].color, "red");
  EXPECT_EQ(plan.markers[1].color, "green");
  EXPECT_EQ(plan.scene.head_side_mm, 32.0);
  for (const MarkerSpec& m : plan.markers) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& p : m.layout_mm) mean += p / m.layout_mm.size();
    EXPECT_LT(mean.norm(), 1e-12);
    EXPECT_EQ(m.layout_mm.size(), 3u);
  }
  EXPECT_FALSE(plan.HasTimes());
}

TEST(TestPlan, RoundTripsThroughItsYaml) {
  const TestPlan plan = ParseTestPlan(
      std::string(kBase) +
          "  - {id: t1, pressures: [1, 2, 3, 4, 5], actuate_s: 1, release_s: 4,"
          " residual_offset_mm: [0.1, 0]}\n"
          "  - {id: t2, pressures: [1, 0, 0, 0, 0], skipped: true}\n"
          "scene: {head_lift_mm: 0.6, head_tilt_deg: 1}\n",
      "p.yaml");
  ASSERT_EQ(plan.tests.size(), 1u);  // a skipped test is not a test point
  ASSERT_EQ(plan.skipped_tests.size(), 1u);
  EXPECT_TRUE(plan.HasTimes());
  const TestPlan again = ParseTestPlan(TestPlanToYaml(plan, "."), "again.yaml");
  ASSERT_EQ(again.skipped_tests.size(), 1u);
  EXPECT_EQ(again.skipped_tests[0].id, "t2");
  EXPECT_EQ(again.tests[0].pressures, plan.tests[0].pressures);
  EXPECT_EQ(*again.tests[0].release_s, 4.0);
  EXPECT_EQ(again.tests[0].residual_offset_mm,
            plan.tests[0].residual_offset_mm);
  EXPECT_EQ(again.scene.head_lift_mm, 0.6);
  EXPECT_EQ(again.scene.head_tilt_deg, 1.0);
  for (size_t i = 0; i < plan.markers[1].layout_mm.size(); ++i) {
    EXPECT_LT(
        (again.markers[1].layout_mm[i] - plan.markers[1].layout_mm[i]).norm(),
        1e-8);
  }
}

// Windows that do not fit the plan's holds and rests would average a moving
// head; dots closer than their diameter merge into one blob.
TEST(TestPlan, RefusesWindowsLongerThanAHoldOrARestAndOverlappingDots) {
  const std::string t1 =
      "  - {id: a, pressures: [1, 2, 3, 4, 5], actuate_s: 2, "
      "release_s: 7}\n";
  const std::string t2 =
      "  - {id: b, pressures: [1, 2, 3, 4, 5], actuate_s: 8, release_s: 12}\n";
  const auto windows_error = [&](const std::string& yaml) {
    return InputErrorOf(
        [&] { CheckWindowsFitTheTimes(ParseTestPlan(yaml, "plan.yaml")); });
  };
  EXPECT_EQ(windows_error(std::string(kBase) + t1 + t2), "");
  EXPECT_NE(windows_error("windows: {length_s: 6}\n" + std::string(kBase) + t1)
                .find("plan.yaml: test a: the hold (5 s) is shorter than "
                      "windows.length_s (6 s)"),
            std::string::npos);
  EXPECT_NE(
      windows_error("windows: {length_s: 2}\n" + std::string(kBase) + t1 + t2)
          .find("plan.yaml: test b: actuated only 1 s after a's "
                "release, less than windows.length_s (2 s)"),
      std::string::npos);
  EXPECT_NE(
      PlanError(std::string(kBase) + t1 +
                "markers:\n  - {head: left, color: red, dots: 3, "
                "dot_diameter_mm: 4, layout_mm: [[0, 0], [6, 0], [3, 2]]}\n"
                "  - {head: right, color: green}\n")
          .find("layout_mm: dots 1 and 3 are 3.61 mm apart, less than a "
                "dot's diameter (4 mm)"),
      std::string::npos);
}

TEST(TestPlan, ErrorsNameTheLineAndSayWhatToChange) {
  EXPECT_NE(
      PlanError(std::string(kBase) + "  - {id: a, pressures: [1, 2]}\n")
          .find("plan.yaml:4: pressures: mechanism 'floating' has 5 actuators"),
      std::string::npos);
  EXPECT_NE(
      PlanError(std::string(kBase) + "  - {id: a, pressures: [1, 2, 3, 4, "
                                     "5], actuate_s: 3, release_s: 2}\n")
          .find("release_s: must be later than actuate_s"),
      std::string::npos);
  EXPECT_NE(PlanError(std::string(kBase) +
                      "  - {id: a, pressures: [1, 2, 3, 4, 5], "
                      "actuate_s: 1, release_s: 2}\n"
                      "  - {id: b, pressures: [1, 2, 3, 4, 5]}\n")
                .find("some tests have times"),
            std::string::npos);
  EXPECT_NE(PlanError("mechanism: tripod\npressure_unit: psi\ntests: []\n")
                .find("plan.yaml:1: mechanism:"),
            std::string::npos);
  EXPECT_NE(PlanError("mechanism: delta\npressure_unit: atm\ntests: []\n")
                .find("pressure_unit: must be psi, kpa, mpa or bar"),
            std::string::npos);
  EXPECT_NE(PlanError("mechanism: delta\npressure_unit: psi\nmarkers:\n"
                      "  - {head: head, color: purple}\ntests:\n"
                      "  - {id: a, pressures: [1, 2, 3]}\n")
                .find("'purple' is not one of"),
            std::string::npos);
  EXPECT_NE(PlanError("mechanism: delta\npressure_unit: psi\ntest:\n")
                .find("unknown key"),
            std::string::npos);
  const std::string delta_test = "tests:\n  - {id: a, pressures: [1, 2, 3]}\n";
  EXPECT_NE(PlanError("mechanism: delta\npressure_unit: psi\ncalibration:\n"
                      "  tag: {id: 1}\n  mm_per_px: 0.2\n" +
                      delta_test)
                .find("give one scale: tag, mm_per_px or scale_from_dots"),
            std::string::npos);
  EXPECT_NE(PlanError("mechanism: delta\npressure_unit: psi\nmarkers:\n"
                      "  - {head: head, hsv: [0, 200, 0, 255, 0, 255]}\n" +
                      delta_test)
                .find("plan.yaml:4: hsv: hue bounds must be 0..179"),
            std::string::npos);
}

// Every wrong shape yaml-cpp would otherwise report as its own exception
// (no file name) is a located error naming the key.
TEST(TestPlan, WrongShapesAreLocatedErrorsNeverYamlCppExceptions) {
  const std::string head = "mechanism: delta\npressure_unit: psi\n";
  const std::string tests = "tests:\n  - {id: a, pressures: [1, 1, 1]}\n";
  const struct {
    std::string yaml, expected;
  } cases[] = {
      {head + "calibration: 5\n" + tests,
       "plan.yaml:3: calibration: must be a map of key: value"},
      {head + "scene: [1, 2]\n" + tests,
       "plan.yaml:3: scene: must be a map of key: value"},
      {head + "windows: 3\n" + tests,
       "plan.yaml:3: windows: must be a map of key: value"},
      {head + "calibration: {tag: [1]}\n" + tests,
       "plan.yaml:3: tag: must be a map of key: value"},
      {head + "tests:\n  - 5\n", "plan.yaml:4: tests entry: must be a map"},
      {head + "markers:\n  - red\n" + tests,
       "plan.yaml:4: markers entry: must be a map"},
      {head + "? [a, b]\n: 1\n" + tests,
       "plan.yaml:3: test plan: keys must be plain names"},
      {head + "pressure_unit: kpa\n" + tests,
       "plan.yaml:3: pressure_unit: given twice; keep one"},
      {"mechanism: {a: 1}\npressure_unit: psi\n" + tests,
       "plan.yaml:1: mechanism: must be a non-empty name"},
      {head + "tests:\n  - {id: a, pressures: [1, 1, 1]}\n"
              "  - {id: a, pressures: [2, 1, 1]}\n",
       "plan.yaml:5: id: 'a' is used twice"},
      {head + "tests:\n  - {id: \"a\\0b\", pressures: [1, 1, 1]}\n",
       "plan.yaml:4: id: 'a' holds control character 0x00"},
      {head + "tests:\n  - {id: \"a\\nb\", pressures: [1, 1, 1]}\n",
       "plan.yaml:4: id: 'a' holds control character 0x0A"},
      {head + "x: " + std::string(100000, '[') + std::string(100000, ']') +
           "\n" + tests,
       "plan.yaml:3: not valid YAML"},
      // Names the file system refuses (longer than a file name may be) are
      // missing files, not file-system exceptions.
      {"mechanism: " + std::string(300, 'm') + "\npressure_unit: psi\n" + tests,
       "plan.yaml:1: mechanism: mechanism '" + std::string(300, 'm') +
           "': no such mechanism"},
      {head + "constants: " + std::string(300, 'c') + ".yaml\n" + tests,
       "plan.yaml:3: constants: "},
      // Numbers no bench has (issue 30: a render that failed allocating, a
      // misfit of "inf mm", a camera "-0 mm" from a tag).
      {head + "scene: {hold_s: 1e9}\n" + tests,
       "plan.yaml:3: hold_s: must be at most 86400"},
      {head + "scene: {head_lift_mm: 7}\n" + tests,
       "plan.yaml:3: head_lift_mm: must be at most 5"},
      {head + "calibration: {mm_per_px: 1e308}\n" + tests,
       "plan.yaml:3: mm_per_px: 1e+308 mm per pixel is no bench camera's"},
      {head + "calibration: {tag: {id: 0, size_mm: 1e-9}}\n" + tests,
       "plan.yaml:3: size_mm: 1e-09 mm is no printed tag's side"},
      {head + "calibration: {focal_length_35mm: 1e308}\n" + tests,
       "plan.yaml:3: focal_length_35mm: 1e+308 mm is no camera's"},
      {head + "tests:\n  - {id: a, pressures: [1e300, 1, 1]}\n",
       "plan.yaml:4: pressures: 1e+300 psi is above 100 MPa"},
      {head + "tests:\n  - {id: a, pressures: [-1, 1, 1]}\n",
       "plan.yaml:4: pressures: -1 psi is negative"},
  };
  for (const auto& c : cases) {
    EXPECT_NE(PlanError(c.yaml).find(c.expected), std::string::npos)
        << PlanError(c.yaml) << "\nfor:\n"
        << c.yaml.substr(0, 200);
  }
}

TEST(TestPlan, LoadRefusesDevicesAndHugeFilesBeforeReading) {
  EXPECT_THROW(LoadTestPlan("/dev/zero"), InputError);
  const std::string path =
      (TestScratch().dir() / "softbench_huge_plan.yaml").string();
  std::ofstream(path) << "mechanism: delta\n# " << std::string(5 << 20, 'x')
                      << "\n";
  const std::string message = InputErrorOf([&] { LoadTestPlan(path); });
  EXPECT_NE(message.find("is too large for a test plan"), std::string::npos)
      << message;
}

TEST(TestPlan, MeasurementKeysRoundTrip) {
  const TestPlan plan = ParseTestPlan(
      "mechanism: delta\npressure_unit: psi\ncalibration:\n"
      "  scale_from_dots: true\n  image_rotation_deg: 90\n"
      "  focal_length_35mm: 26\n  distortion_tolerance: 0.001\n"
      "markers:\n  - {head: head, hsv: [172, 8, 90, 255, 40, 255]}\n"
      "tests:\n  - {id: a, pressures: [1, 2, 3]}\n",
      "plan.yaml");
  const TestPlan again = ParseTestPlan(TestPlanToYaml(plan, "."), "again.yaml");
  EXPECT_TRUE(again.calibration.scale_from_dots);
  EXPECT_EQ(again.calibration.image_rotation_deg, 90.0);
  EXPECT_EQ(again.calibration.focal_length_35mm, 26.0);
  EXPECT_EQ(again.calibration.distortion_tolerance, 0.001);
  ASSERT_TRUE(again.markers[0].hsv);
  EXPECT_EQ(*again.markers[0].hsv,
            (std::array<int, 6>{172, 8, 90, 255, 40, 255}));
}

TEST(TestPlan, DocumentedExampleParses) {
  const std::string doc =
      ReadTextFile(std::string(SOFTBENCH_SOURCE_DIR) + "/docs/file-formats.md",
                   "doc", 1 << 20);
  const size_t section = doc.find("## Test plan");
  const size_t begin = doc.find("```yaml\n", section) + 8;
  const TestPlan plan =
      ParseTestPlan(doc.substr(begin, doc.find("```", begin) - begin),
                    "docs/file-formats.md");
  EXPECT_EQ(plan.tests.size(), 2u);
  EXPECT_EQ(plan.tests[1].residual_offset_mm.x(), 0.1);
  EXPECT_EQ(*plan.calibration.tag->center_mm, Eigen::Vector2d(60, -60));
}

}  // namespace
}  // namespace softbench
