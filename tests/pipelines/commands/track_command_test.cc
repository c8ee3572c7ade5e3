// The measurement commands track and tune, on a short rendered clip, and
// their messages for bad input.
#include "pipelines/commands/track_command.h"

#include <gtest/gtest.h>
#include <libheif/heif.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "pipelines/commands/render_command.h"
#include "pipelines/commands/tune_command.h"
#include "pipelines/commands/validate_command.h"
#include "tests/support/input_error_matchers.h"
#include "tests/support/rendered_clip.h"
#include "tests/support/scratch_directory.h"
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
  // One 5 s 720p clip for every test of the suite (rendered once for all
  // their processes), in a scratch folder of the suite's own.
  static void SetUpTestSuite() {
    scratch_ = new ScratchDirectory();
    RenderSharedClip(QuickRenderOptions(*scratch_, kPlan), "track_suite");
  }
  static void TearDownTestSuite() {
    delete scratch_;
    scratch_ = nullptr;
  }
  static std::string Path(const std::string& name) {
    return scratch_->Path(name);
  }
  static std::string WritePlan(const std::string& name,
                               const std::string& text) {
    return scratch_->Write(name, text);
  }
  // Runs track and returns the InputError message ("" if none).
  static std::string TrackError(const std::string& plan_path) {
    TrackCommandOptions options;
    options.plan_path = plan_path;
    options.video_path = Path("clip.mp4");
    options.output_path = Path("error_trajectory.csv");
    options.quiet = true;
    std::ostringstream out;
    const std::string message = InputErrorOf([&] { RunTrack(options, out); });
    if (!message.empty()) {
      EXPECT_FALSE(fs::exists(options.output_path));
    }
    return message;
  }
  static ScratchDirectory* scratch_;
};

ScratchDirectory* TrackCommandTest::scratch_ = nullptr;

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
            "frame,time_s,head,u_px,v_px,y_mm,z_mm,sigma_mm,u_y_mm,u_z_mm,"
            "dots_found,dots,rotation_rad,lift_mm,tilt_y_rad,tilt_z_rad,"
            "binary_y_mm,binary_z_mm,full_frame,registered,camera_dx_px,camera_"
            "dy_px,camera_roll_rad,note");
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
  options.source_path = Path("clip.mp4");
  options.at_s = 0.5;
  options.output_dir = Path("tune");
  std::ostringstream out;
  ASSERT_EQ(RunTune(options, out), 0);
  EXPECT_NE(out.str().find("red: 3 dots"), std::string::npos) << out.str();
  for (const char* png :
       {"tune/tune_0.50s_frame.png", "tune/tune_red_0.50s_mask.png",
        "tune/tune_red_0.50s_overlay.png"}) {
    EXPECT_FALSE(cv::imread(Path(png)).empty()) << png;
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
  options.source_path =
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

// The page's DOM once its script has run in headless Chromium, opened at
// `fragment` (which moves sliders as a person would).
std::string TunePageDom(const std::string& page, const std::string& fragment) {
  const std::string dom = page + ".dom";
  const std::string command =
      "chromium --headless --no-sandbox --disable-gpu --no-first-run "
      "--disable-background-networking --user-data-dir=" +
      page + ".profile --virtual-time-budget=20000 --dump-dom 'file://" + page +
      fragment + "' > " + dom + " 2>/dev/null";
  EXPECT_EQ(std::system(command.c_str()), 0);
  std::ifstream stream(dom);
  std::stringstream text;
  text << stream.rdbuf();
  return text.str();
}

// The text of the element with `id` in a dumped DOM.
std::string ElementText(const std::string& dom, const std::string& id) {
  const std::string open = "id=\"" + id + "\">";
  const size_t start = dom.find(open);
  if (start == std::string::npos) return "(no " + id + ")";
  const size_t from = start + open.size();
  return dom.substr(from, dom.find('<', from) - from);
}

TEST_F(TrackCommandTest, TunePageSlidersMoveTheMaskAndItsYamlFindsTheDots) {
  TuneCommandOptions options;
  options.source_path = Path("clip.mp4");
  options.at_s = 0.5;
  options.color = "red,green";
  options.output_dir = Path("tune_page");
  std::ostringstream out;
  ASSERT_EQ(RunTune(options, out), 0);
  // The clip has red dots only: green is reported absent, not found.
  EXPECT_NE(out.str().find("green: absent"), std::string::npos) << out.str();
  const std::string page = Path("tune_page/tune.html");
  const std::string as_written = TunePageDom(page, "");
  EXPECT_EQ(ElementText(as_written, "dots-red"), "3");
  EXPECT_EQ(ElementText(as_written, "dots-green"), "0");
  EXPECT_EQ(ElementText(as_written, "status-green").rfind("absent", 0), 0u);
  const std::string yaml = ElementText(as_written, "yaml");
  const size_t red = yaml.find("{color: red, hsv: [");
  ASSERT_NE(red, std::string::npos) << yaml;
  const size_t open = yaml.find('[', red);
  const std::string hsv =
      yaml.substr(open, yaml.find(']', open) - open + 1);  // "[...]"
  // Sliders moved to a hue no dot has: the mask empties, the YAML follows.
  const std::string moved = TunePageDom(page, "#red=90,100,0,255,0,255");
  EXPECT_EQ(ElementText(moved, "dots-red"), "0");
  EXPECT_LT(std::stoi(ElementText(moved, "pixels-red")),
            std::stoi(ElementText(as_written, "pixels-red")));
  EXPECT_NE(ElementText(moved, "yaml")
                .find("{color: red, hsv: [90, 100, 0, 255, 0, 255]}"),
            std::string::npos)
      << ElementText(moved, "yaml");
  // The page's YAML pasted into the plan: track finds every dot in every
  // frame with it.
  TrackCommandOptions track;
  track.plan_path = WritePlan(
      "tuned.yaml", std::string(kPlan) +
                        "markers:\n  - {head: head, color: red, hsv: " + hsv +
                        "}\n");
  track.video_path = Path("clip.mp4");
  track.output_path = Path("tuned.csv");
  track.quiet = true;
  ASSERT_EQ(RunTrack(track, out), 0) << hsv;
  std::ifstream csv(track.output_path);
  std::string line;
  std::getline(csv, line);
  int rows = 0, complete = 0;
  while (std::getline(csv, line)) {
    ++rows;
    complete += line.find(",3,3,") != std::string::npos;
  }
  EXPECT_GT(rows, 100);
  EXPECT_EQ(complete, rows) << hsv;
  // And validate, with that plan, measures the test.
  ValidateCommandOptions validate;
  validate.video_paths = {Path("clip.mp4")};
  validate.plan_path = track.plan_path;
  validate.output_directory = Path("tuned_report");
  validate.quiet = true;
  ASSERT_EQ(RunValidate(validate, out), 0) << hsv;
  EXPECT_NE(out.str().find("1 test points (times from the plan), 1 measured"),
            std::string::npos)
      << out.str();
}

// `bgr` written as an iPhone writes photos: HEIC (HEVC in HEIF), by libheif
// with x265.
void WriteHeic(const cv::Mat& bgr, const std::string& path) {
  heif_context* context = heif_context_alloc();
  heif_encoder* encoder = nullptr;
  ASSERT_EQ(heif_context_get_encoder_for_format(context, heif_compression_HEVC,
                                                &encoder)
                .code,
            heif_error_Ok);
  heif_encoder_set_lossy_quality(encoder, 95);
  heif_image* image = nullptr;
  heif_image_create(bgr.cols, bgr.rows, heif_colorspace_RGB,
                    heif_chroma_interleaved_RGB, &image);
  heif_image_add_plane(image, heif_channel_interleaved, bgr.cols, bgr.rows, 8);
  int stride = 0;
  uint8_t* plane =
      heif_image_get_plane(image, heif_channel_interleaved, &stride);
  cv::Mat rgb(bgr.rows, bgr.cols, CV_8UC3, plane, static_cast<size_t>(stride));
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  ASSERT_EQ(
      heif_context_encode_image(context, image, encoder, nullptr, nullptr).code,
      heif_error_Ok);
  ASSERT_EQ(heif_context_write_to_file(context, path.c_str()).code,
            heif_error_Ok);
  heif_image_release(image);
  heif_encoder_release(encoder);
  heif_context_free(context);
}

TEST_F(TrackCommandTest, TuneTakesPngJpegAndHeicPhotos) {
  // Photos of the bench: the clip's frame saved as each.
  TuneCommandOptions options;
  options.source_path = Path("clip.mp4");
  options.at_s = 0.5;
  options.output_dir = Path("tune_photo_source");
  std::ostringstream out;
  ASSERT_EQ(RunTune(options, out), 0);
  const cv::Mat frame =
      cv::imread(Path("tune_photo_source/tune_0.50s_frame.png"));
  ASSERT_FALSE(frame.empty());
  cv::imwrite(Path("bench.png"), frame);
  cv::imwrite(Path("bench.jpg"), frame, {cv::IMWRITE_JPEG_QUALITY, 92});
  WriteHeic(frame, Path("bench.HEIC"));
  for (const char* photo : {"bench.png", "bench.jpg", "bench.HEIC"}) {
    options.source_path = Path(photo);
    options.output_dir = Path(std::string("tune_") + photo);
    std::ostringstream said;
    ASSERT_EQ(RunTune(options, said), 0) << photo;
    EXPECT_NE(said.str().find("red: 3 dots"), std::string::npos)
        << photo << ": " << said.str();
    EXPECT_TRUE(fs::exists(options.output_dir + "/tune.html")) << photo;
  }
  options.source_path = Path("broken.heic");
  std::ofstream(options.source_path) << "not really";
  EXPECT_THAT([&] { RunTune(options, out); },
              ::testing::ThrowsMessage<InputError>(::testing::StartsWith(
                  options.source_path + ": not a readable HEIC/HEIF photo")));
}

TEST_F(TrackCommandTest, TuneRejectsAnUnknownColour) {
  TuneCommandOptions options;
  options.source_path = Path("clip.mp4");
  options.color = "purple";
  std::ostringstream out;
  EXPECT_THAT([&] { RunTune(options, out); },
              ThrowsInputErrorWith("", "--color", "'purple' is not red"));
}

// --out is checked before the picture is read, and made only once there is
// something to write into it (issue 31: it was created before the checks).
TEST_F(TrackCommandTest, TuneChecksItsOutBeforeAnyWork) {
  TuneCommandOptions options;
  options.source_path = Path("no_such_photo.png");
  options.color = "red";
  std::ostringstream out;
  options.output_dir = WritePlan("a_file", "x");
  EXPECT_THAT(
      [&] { RunTune(options, out); },
      ThrowsInputErrorWith("a_file", "--out", "exists and is not a folder"));
  options.output_dir = "/proc/softbench_tune";
  EXPECT_THAT([&] { RunTune(options, out); },
              ThrowsInputErrorWith("/proc", "--out", "is not writable"));
  options.output_dir = Path("tune_new");
  EXPECT_THAT([&] { RunTune(options, out); },
              ThrowsInputErrorWith("no_such_photo.png", "", ""));
  EXPECT_FALSE(fs::exists(options.output_dir));
}

}  // namespace
}  // namespace softbench
