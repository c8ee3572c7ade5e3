// The measurement commands track and tune, on a short rendered clip, and
// their messages for bad input.
#include "pipelines/commands/track_command.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "pipelines/commands/render_command.h"
#include "pipelines/commands/tune_command.h"
#include "util/input_error.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

constexpr char kPlan[] = R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 3, size_mm: 25}
tests:
  - {id: a, pressures: [6, 6, 0], actuate_s: 1.0, release_s: 2.0}
)";

class TrackCommandTest : public ::testing::Test {
 protected:
  // One 5 s 720p clip for every test of the suite.
  static void SetUpTestSuite() {
    // One folder per process: ctest may run these tests in parallel.
    dir_ = fs::temp_directory_path() /
           ("softbench_track_command_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "plan.yaml") << kPlan;
    RenderCommandOptions render;
    render.plan_path = (dir_ / "plan.yaml").string();
    render.output_path = (dir_ / "clip.mp4").string();
    render.truth_path = (dir_ / "truth.csv").string();
    render.resolution = "720p";
    render.preset = "veryfast";
    render.quiet = true;
    std::ostringstream out;
    RunRender(render, out);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string Path(const std::string& name) {
    return (dir_ / name).string();
  }
  static std::string WritePlan(const std::string& name,
                               const std::string& text) {
    std::ofstream(Path(name)) << text;
    return Path(name);
  }
  // Runs track and returns the InputError message ("" if none).
  static std::string TrackError(const std::string& plan_path) {
    TrackCommandOptions options;
    options.plan_path = plan_path;
    options.video_path = Path("clip.mp4");
    options.output_path = Path("error_trajectory.csv");
    options.quiet = true;
    std::ostringstream out;
    try {
      RunTrack(options, out);
    } catch (const InputError& e) {
      EXPECT_FALSE(fs::exists(options.output_path));
      return e.what();
    }
    return "";
  }
  static fs::path dir_;
};

fs::path TrackCommandTest::dir_;

TEST_F(TrackCommandTest, WritesOneRowPerFrameAndHead) {
  TrackCommandOptions options;
  options.plan_path = Path("plan.yaml");
  options.video_path = Path("clip.mp4");
  options.output_path = Path("trajectory.csv");
  options.quiet = true;
  std::ostringstream out;
  ASSERT_EQ(RunTrack(options, out), 0);
  EXPECT_NE(out.str().find("scale from tag 3"), std::string::npos) << out.str();
  std::ifstream csv(options.output_path);
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "frame,time_s,head,u_px,v_px,y_mm,z_mm,sigma_mm,dots_found,dots,"
            "rotation_rad,binary_y_mm,binary_z_mm,full_frame,registered,"
            "camera_dx_px,camera_dy_px,camera_roll_rad,note");
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_NE(line.find(",head,"), std::string::npos) << line;
    EXPECT_NE(line.find(",3,3,"), std::string::npos) << line;
  }
  EXPECT_EQ(rows, 150);  // release at 2 s + 3 s of rest, 30 fps, one head
}

TEST_F(TrackCommandTest, WrongTagIdSaysWhichWereSeen) {
  std::string plan = kPlan;
  plan.replace(plan.find("id: 3"), 5, "id: 5");
  const std::string message = TrackError(WritePlan("wrong_tag.yaml", plan));
  EXPECT_NE(message.find("clip.mp4: found tag id(s) 3 in the first 10 "
                         "frames, but the plan's calibration.tag is id 5"),
            std::string::npos)
      << message;
}

TEST_F(TrackCommandTest, MissingColourNamesTheFirstFrame) {
  const std::string plan =
      std::string(kPlan) + "markers:\n  - {head: head, color: green}\n";
  const std::string message = TrackError(WritePlan("green.yaml", plan));
  EXPECT_NE(message.find("clip.mp4: first frame measured (t = 0.000 s): head "
                         "'head': found 0 green dot-like blobs"),
            std::string::npos)
      << message;
}

TEST_F(TrackCommandTest, TooManyDotsForTheHeadIsReported) {
  const std::string plan =
      std::string(kPlan) + "markers:\n  - {head: head, color: red, dots: 4}\n";
  const std::string message = TrackError(WritePlan("four.yaml", plan));
  EXPECT_NE(message.find("found 3 red dot-like blobs"), std::string::npos)
      << message;
  EXPECT_NE(message.find("the plan says 4 dots"), std::string::npos) << message;
}

TEST_F(TrackCommandTest, NoScaleIsAnError) {
  const std::string plan =
      "mechanism: delta\npressure_unit: psi\ntests:\n  - {id: a, pressures: "
      "[6, 6, 0]}\n";
  const std::string message = TrackError(WritePlan("no_scale.yaml", plan));
  EXPECT_NE(message.find("no_scale.yaml: calibration needs a tag, "
                         "mm_per_px or scale_from_dots"),
            std::string::npos)
      << message;
}

// The largest |y|, |z| displacement in a trajectory CSV.
double LargestDisplacement(const std::string& path) {
  std::ifstream csv(path);
  std::string line;
  std::getline(csv, line);
  double largest = 0.0;
  while (std::getline(csv, line)) {
    std::stringstream fields(line);
    std::string field;
    for (int i = 0; i < 7 && std::getline(fields, field, ','); ++i) {
      if (i >= 5) largest = std::max(largest, std::abs(std::stod(field)));
    }
  }
  return largest;
}

TEST_F(TrackCommandTest, ScalesWithoutATagAgree) {
  // The tag, the dots' known spacing and a given factor give one answer
  // (the camera faces the plane; 0.2687 mm/px is 720p's at the dot plane).
  const std::string base =
      "mechanism: delta\npressure_unit: psi\n"
      "tests:\n  - {id: a, pressures: [6, 6, 0], "
      "actuate_s: 1.0, release_s: 2.0}\n";
  TrackCommandOptions options;
  options.video_path = Path("clip.mp4");
  options.quiet = true;
  std::ostringstream out;
  std::vector<double> largest;
  for (const std::string& scale :
       {std::string("  tag: {family: tag36h11, id: 3, size_mm: 25}\n"),
        std::string("  scale_from_dots: true\n"),
        std::string("  mm_per_px: 0.26916\n")}) {
    options.plan_path =
        WritePlan("scale.yaml",
                  base + "calibration:\n" + scale + "  plane_offset_mm: 16\n");
    options.output_path = Path("scale.csv");
    ASSERT_EQ(RunTrack(options, out), 0) << scale;
    largest.push_back(LargestDisplacement(options.output_path));
  }
  EXPECT_NE(out.str().find("scale from dots of head 'head'"), std::string::npos)
      << out.str();
  EXPECT_GT(largest[0], 1.0);  // (6, 6, 0) psi moves the head ~1.3 mm
  EXPECT_NEAR(largest[1], largest[0], 0.01);
  EXPECT_NEAR(largest[2], largest[0], 0.01);
}

TEST_F(TrackCommandTest, TuneWritesImagesAndARangeThatHoldsTheDots) {
  TuneCommandOptions options;
  options.video_path = Path("clip.mp4");
  options.at_s = 0.5;
  options.output_dir = Path("tune");
  std::ostringstream out;
  ASSERT_EQ(RunTune(options, out), 0);
  EXPECT_NE(out.str().find("red: 3 dots"), std::string::npos) << out.str();
  for (const char* kind : {"frame", "mask", "overlay"}) {
    const std::string png =
        Path(std::string("tune/tune_red_0.50s_") + kind + ".png");
    EXPECT_FALSE(cv::imread(png).empty()) << png;
  }
  // The suggested range is printed ready to paste, and covers every dot
  // pixel with nothing else inside.
  EXPECT_NE(out.str().find("covers 100.0 % of them, 0 other pixels inside"),
            std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("  hsv: ["), std::string::npos) << out.str();
}

// An iPhone's default video (the phone sample: HLG 10-bit HEVC, stored
// sideways with its rotation): tune's SDR colours find the dots with the
// built-in range, and its pictures are upright.
TEST_F(TrackCommandTest, TuneFindsTheDotsOnHdrPortraitFootage) {
  TuneCommandOptions options;
  options.video_path =
      std::string(SOFTBENCH_SOURCE_DIR) + "/samples/phone/phone.mp4";
  options.at_s = 0.5;
  options.output_dir = Path("tune");
  std::ostringstream out;
  ASSERT_EQ(RunTune(options, out), 0);
  EXPECT_NE(out.str().find("red: 3 dots"), std::string::npos) << out.str();
  // Named by the frame's own time (variable frame rate: 0.505 s).
  cv::Mat frame;
  for (const auto& entry : fs::directory_iterator(Path("tune"))) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 10 && name.substr(name.size() - 10) == "_frame.png") {
      frame = cv::imread(entry.path().string());
    }
  }
  EXPECT_EQ(frame.cols, 1080);
  EXPECT_EQ(frame.rows, 1920);
}

TEST_F(TrackCommandTest, TuneRejectsAnUnknownColour) {
  TuneCommandOptions options;
  options.video_path = Path("clip.mp4");
  options.color = "purple";
  std::ostringstream out;
  try {
    RunTune(options, out);
    FAIL() << "accepted purple";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--color: 'purple' is not red"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace softbench
