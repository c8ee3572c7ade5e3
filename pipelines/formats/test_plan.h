#ifndef SOFTBENCH_PIPELINES_FORMATS_TEST_PLAN_H_
#define SOFTBENCH_PIPELINES_FORMATS_TEST_PLAN_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "model/actuator_model.h"
#include "model/characterised_range.h"
#include "model/mechanism.h"

namespace softbench {

// tag36h11's ids run from 0 to kTag36h11Codes - 1.
inline constexpr int kTag36h11Codes = 587;

// The AprilTag that gives scale and axes (thesis 4.1.3 used a pixel-to-mm
// factor instead). Its printed +x edge is world +y, its printed "up" world +z.
struct TagSpec {
  std::string family = "tag36h11";
  int id = 0;
  // Outer edge of the black border [mm] (AprilTag 3's convention).
  double size_mm = 25.0;
  // Centre on the tag plane, world (y, z) [mm]; unset: beside the ring.
  std::optional<Eigen::Vector2d> center_mm;
};

struct CalibrationSpec {
  std::optional<TagSpec> tag;
  // Height of the dot plane (head tops) above the tag plane [mm]: the thesis
  // heads are 26 mm tall, the ring 10 mm.
  double plane_offset_mm = 16.0;
  std::string intrinsics_path;  // OpenCV YAML; empty: none
  // Without an intrinsics file: the lens's 35 mm-equivalent focal length
  // (the thesis's iPhone 12 Pro main camera at 1x: 52 mm), no distortion.
  double focal_length_35mm = 52.0;
  // Without a tag: a given scale at the image centre and the image's
  // rotation (world +y is image right turned counter-clockwise by it) ...
  std::optional<double> mm_per_px;
  double image_rotation_deg = 0.0;
  // ... or the scale from the first head's dots, a known distance apart
  // (their layout_mm), with that rotation.
  bool scale_from_dots = false;
  // Largest relative scale difference across the field before the
  // distortion check warns (see docs/measurement.md).
  double distortion_tolerance = 0.002;
};

// The dots on one head (thesis fig. 4.7: red dots on the feedback head).
struct MarkerSpec {
  int head = 0;               // index into the mechanism's heads
  std::string color = "red";  // a name of DotColors()
  int dots = 3;
  double dot_diameter_mm = 4.0;
  // Dot centres relative to the head centre [mm]; a head's position is the
  // centre of its dots, so the layout is centred (mean zero).
  std::vector<Eigen::Vector2d> layout_mm;
  // HSV bounds [h_low, h_high, s_low, s_high, v_low, v_high] (OpenCV units,
  // as `softbench tune` prints); unset: the colour's built-in range.
  std::optional<std::array<int, 6>> hsv;
};

// The marker's HSV bounds: the plan's, else its colour's built-in ones.
std::array<int, 6> MarkerHsvBounds(const MarkerSpec& marker);

struct TestPoint {
  std::string id;
  Eigen::VectorXd pressures;  // in the plan's pressure unit
  std::optional<double> actuate_s;
  std::optional<double> release_s;
  // Rendering only: a permanent slip of every head after release [mm], to
  // emulate hysteresis (validation must flag this test).
  Eigen::Vector2d residual_offset_mm = Eigen::Vector2d::Zero();
};

// Rendering-only settings of the plan's `scene` section.
struct SceneSpec {
  double settle_time_constant_s = 0.4;  // first-order settling
  double creep_fraction = 0.0;  // extra displacement approached during a hold
  double creep_time_constant_s = 8.0;
  double head_side_mm = 0.0;  // triangle side; 0: 40 (one head) or 32
  double lead_in_s = 2.0;     // before the first test, when times are made
  double hold_s = 5.0;        // actuate to release, when times are made
  double rest_s = 3.0;        // release to the next actuation / the end
  // Heads out of the plane while actuated (issue 27): each test lifts each
  // head toward the camera by up to head_lift_mm and tilts it by up to
  // head_tilt_deg in a direction of its own, drawn per test and head from
  // a fixed seed (the same for every render of the plan); at release the
  // head settles back flat. 0: heads stay in the plane.
  double head_lift_mm = 0.0;
  double head_tilt_deg = 0.0;
};

// A test plan (docs/file-formats.md, "Test plan"): one format for `render` and
// `validate`.
struct TestPlan {
  std::string path;            // for messages
  std::string mechanism_name;  // as written: a built-in name or a path
  std::string mechanism_path;  // resolved file; empty for a built-in
  std::string constants_path;  // resolved file; empty: the thesis's
  Mechanism mechanism;
  ForceModel force_model;
  // Where the constants hold (their file's, else the thesis's protocol).
  CharacterisedRange range;
  std::string pressure_unit = "psi";
  double mpa_per_unit = 0.0;
  CalibrationSpec calibration;
  std::vector<MarkerSpec> markers;  // one per head, in head order
  std::vector<TestPoint> tests;     // the tests the bench performed, in order
  // Entries marked `skipped: true`: listed in the protocol but not done on
  // the bench (no motion expected; reported as skipped, never scored).
  std::vector<TestPoint> skipped_tests;
  double window_s = 1.0;
  double hysteresis_tolerance_mm = 0.05;
  SceneSpec scene;

  // True when every test has actuate_s and release_s.
  bool HasTimes() const;
};

// Throws InputError naming the plan and the test when a window (window_s
// long, ending at an actuation or a release) does not fit inside that
// test's hold or the rest before it, so that it would average a moving
// head. Validation from the plan's times calls it; rendering does not need
// it (a render plan may rest for less than a window).
void CheckWindowsFitTheTimes(const TestPlan& plan);

// Parses a plan; `path` names it in messages and anchors relative file names
// (mechanism, constants). Throws InputError naming the line and key.
TestPlan ParseTestPlan(std::string_view yaml, const std::string& path);
TestPlan LoadTestPlan(const std::string& path);

// The plan as YAML with every default written out (what render saves as "the
// plan with the times used"); file names are made relative to `output_dir`.
std::string TestPlanToYaml(const TestPlan& plan, const std::string& output_dir);

// The default dot layout: `dots` points on a circle toward the corners of the
// head's triangle (or evenly from +z when the head has no three attachments).
std::vector<Eigen::Vector2d> DefaultDotLayout(const Mechanism& mechanism,
                                              int head, int dots,
                                              double head_side_mm);

// Unit vectors from a head toward the other end of each actuator touching it.
std::vector<Eigen::Vector2d> AttachmentDirections(const Mechanism& mechanism,
                                                  int head);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_TEST_PLAN_H_
