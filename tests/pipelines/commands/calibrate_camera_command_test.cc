// `softbench calibrate-camera` on rendered checkerboard photos (its own
// suite: it needs no bench clip).
#include "pipelines/commands/calibrate_camera_command.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "pipelines/measurement/board_views.h"
#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "tests/vision/board_images.h"
#include "util/input_error.h"
#include "vision/video_writer.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

class CalibrateCameraCommandTest : public ScratchDirectoryTest {};

TEST_F(CalibrateCameraCommandTest,
       WritesIntrinsicsFromImagesAndRefusesTheWrongBoard) {
  CameraIntrinsics truth_k =
      CameraIntrinsics::FromEquivalentFocalLength(52.0, 1280, 720);
  truth_k.distortion[0] = -0.1;
  const BoardRenderer boards(truth_k, 9, 6, 20.0);
  fs::create_directories(Path("boards"));
  int seed = 1;
  for (const Camera& view : BoardViews(truth_k, 600.0)) {
    cv::imwrite(Path("boards/view" + std::to_string(seed) + ".png"),
                boards.Render(view, 0.6, seed));
    ++seed;
  }
  // A photo without the board is named, not silently skipped.
  cv::imwrite(Path("boards/wall.png"), cv::Mat(720, 1280, CV_8UC1, 128));
  CalibrateCameraCommandOptions options;
  options.source_path = Path("boards");
  options.square_mm = 20.0;
  options.output_path = Path("camera.yaml");
  std::ostringstream out;
  ASSERT_EQ(RunCalibrateCamera(options, out), 0);
  const std::string said = out.str();
  EXPECT_NE(said.find("reprojection error"), std::string::npos);
  EXPECT_NE(said.find("view  reprojection_error_px\nview1.png  0."),
            std::string::npos)
      << said;
  EXPECT_NE(said.find("no whole board found in 1 view: wall.png"),
            std::string::npos)
      << said;
  EXPECT_NE(said.find("standard errors: fx "), std::string::npos) << said;
  std::ifstream yaml(options.output_path);
  std::stringstream text;
  text << yaml.rdbuf();
  EXPECT_NE(text.str().find("camera_matrix"), std::string::npos);
  EXPECT_NE(text.str().find("distortion_coefficients"), std::string::npos);
  EXPECT_NE(text.str().find("per_view_reprojection_errors"), std::string::npos);
  // The standard errors are the fit's: the truth lies within a few of them.
  const CameraCalibration fitted = LoadCameraCalibration(options.output_path);
  const CameraCalibrationSummary again = CalibrateCamera(
      BoardViewsFromImages(Path("boards"), {{9, 6, 20.0}, 0.5, false}).corners,
      {1280, 720}, {{9, 6, 20.0}, 5, false});
  ASSERT_TRUE(again.converged);
  const CameraCalibration& c = again.calibration;
  EXPECT_EQ(c.view_errors_px.size(), static_cast<size_t>(seed - 1));
  const double truth[4] = {truth_k.fx_px, truth_k.fy_px, truth_k.cx_px,
                           truth_k.cy_px};
  const double fit[4] = {c.camera_matrix(0, 0), c.camera_matrix(1, 1),
                         c.camera_matrix(0, 2), c.camera_matrix(1, 2)};
  for (int i = 0; i < 4; ++i) {
    EXPECT_GT(c.intrinsics_std_px[i], 0.0) << i;
    EXPECT_LT(std::abs(fit[i] - truth[i]), 5 * c.intrinsics_std_px[i] + 0.5)
        << i;
  }
  EXPECT_EQ(fitted.camera_matrix(0, 0), c.camera_matrix(0, 0));

  options.board = "7x5";  // the wrong board: refused with the print's
  options.output_path = Path("camera_wrong.yaml");
  const std::string message =
      InputErrorOf([&] { RunCalibrateCamera(options, out); });
  EXPECT_NE(message.find("give --board 9x6"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(options.output_path));
}

// A 10-bit video (a phone's HDR default) of the boards gives the views the
// same boards' 8-bit photos give: its luma, read as decoded (codes 0-1023),
// reaches OpenCV's board finder scaled to fill 16 bits.
TEST_F(CalibrateCameraCommandTest, TenBitVideoGivesThePhotosViews) {
  const CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(52.0, 640, 360);
  const BoardRenderer boards(k, 9, 6, 20.0);
  fs::create_directories(Path("photos"));
  VideoWriterOptions video;
  video.bit_depth = 10;
  video.crf = 0;  // lossless: the video's frames are the photos
  video.fps = 2.0;
  video.full_range = true;
  VideoWriter writer(Path("boards.mp4"), 640, 360, video);
  int seed = 1;
  for (const Camera& view : BoardViews(k, 600.0)) {
    // A dim print under dim light: squares 100 and 160 of 255.
    cv::Mat grey;
    boards.Render(view, 0.0, seed).convertTo(grey, CV_8U, 60.0 / 255, 100);
    // Named in the video's order (images are read in name order).
    cv::imwrite(Path(fmt::format("photos/view{:02d}.png", seed)), grey);
    cv::Mat bgr;
    cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
    writer.Write(bgr);
    ++seed;
  }
  writer.Close();
  const BoardViewsOptions options{{9, 6, 20.0}, 0.5, false};
  const auto photos = BoardViewsFromImages(Path("photos"), options);
  const auto frames = BoardViewsFromVideo(Path("boards.mp4"), options);
  ASSERT_EQ(photos.corners.size(), static_cast<size_t>(seed - 1));
  ASSERT_EQ(frames.corners.size(), photos.corners.size());
  double worst_px = 0.0;
  for (size_t v = 0; v < photos.corners.size(); ++v) {
    ASSERT_EQ(frames.corners[v].size(), photos.corners[v].size()) << v;
    for (size_t c = 0; c < photos.corners[v].size(); ++c) {
      worst_px = std::max<double>(
          worst_px, cv::norm(frames.corners[v][c] - photos.corners[v][c]));
    }
  }
  // The video's 4:2:0 luma of grey is the photos' grey to within a level.
  EXPECT_LT(worst_px, 0.05);
}

// OpenCV's own sample photos (Debian's opencv-doc): 13 views of a 9 x 6
// board through a real, distorting lens, as OpenCV's calibration sample
// calibrates them (left_intrinsics.yml beside them).
class SampleChessboardPhotosTest : public ScratchDirectoryTest {
 protected:
  void SetUp() override {
    ScratchDirectoryTest::SetUp();
    const fs::path data = "/usr/share/doc/opencv-doc/examples/data";
    ASSERT_TRUE(fs::exists(data / "left01.jpg"))
        << "install opencv-doc (scripts/bootstrap.sh does)";
    fs::create_directories(Path("left"));
    for (const auto& entry : fs::directory_iterator(data)) {
      const std::string name = entry.path().filename().string();
      if (name.size() == 10 && name.rfind("left", 0) == 0 &&
          entry.path().extension() == ".jpg") {
        fs::copy_file(entry.path(), Path("left/" + name));
      }
    }
  }
};

TEST_F(SampleChessboardPhotosTest, GivesEveryViewsErrorAndThePage) {
  CalibrateCameraCommandOptions options;
  options.source_path = Path("left");
  options.board = "9x6";
  options.square_mm = 25.0;
  options.fit_k3 = true;  // as OpenCV's sample does for this lens
  options.output_path = Path("camera.yaml");
  std::ostringstream out;
  ASSERT_EQ(RunCalibrateCamera(options, out), 0);
  const std::string said = out.str();
  for (const char* view :
       {"left01.jpg  0.", "left09.jpg  0.", "left14.jpg  0."}) {
    EXPECT_NE(said.find(view), std::string::npos) << view << "\n" << said;
  }
  EXPECT_NE(said.find("calibrated from 13 of 13 views"), std::string::npos)
      << said;
  const CameraCalibration c = LoadCameraCalibration(options.output_path);
  // OpenCV's sample found fx = fy = 535.9 px, centre (342.3, 235.6) px.
  EXPECT_NEAR(c.camera_matrix(0, 0), 535.9, 0.02 * 535.9);
  EXPECT_NEAR(c.camera_matrix(1, 1), 535.9, 0.02 * 535.9);
  EXPECT_NEAR(c.camera_matrix(0, 2), 342.3, 10.0);
  EXPECT_NEAR(c.camera_matrix(1, 2), 235.6, 10.0);
  EXPECT_LT(c.reprojection_error_px, 0.5);
  // The page: intrinsics with their standard errors, the per-view chart and
  // the coverage chart, drawn in Chromium without a console message.
  const std::string page = Read(Path("camera.html"));
  EXPECT_NE(page.find("<td>fx</td>"), std::string::npos);
  EXPECT_NE(page.find("Reprojection error per view"), std::string::npos);
  EXPECT_NE(page.find("Coverage of the image"), std::string::npos);
  EXPECT_NE(page.find("left13.jpg"), std::string::npos);
  EXPECT_EQ(std::system(("bash " SOFTBENCH_SOURCE_DIR
                         "/report/check_in_chromium.sh " +
                         Path("camera.html") + " >/dev/null")
                            .c_str()),
            0);
}

TEST_F(SampleChessboardPhotosTest, RefusesABoardThePrintDoesNotHave) {
  for (const char* board : {"8x6", "9x5", "10x7"}) {
    CalibrateCameraCommandOptions options;
    options.source_path = Path("left");
    options.board = board;
    options.square_mm = 25.0;
    options.output_path = Path("camera.yaml");
    std::ostringstream out;
    const std::string message =
        InputErrorOf([&] { RunCalibrateCamera(options, out); });
    EXPECT_NE(message.find("give --board 9x6"), std::string::npos) << message;
    EXPECT_NE(message.find(std::string("not the ") + board[0]),
              std::string::npos)
        << message;
    EXPECT_FALSE(fs::exists(options.output_path));
    EXPECT_FALSE(fs::exists(Path("camera.html")));
  }
}

}  // namespace
}  // namespace softbench
