// `softbench calibrate-camera` on rendered checkerboard photos (its own
// suite: it needs no bench clip).
#include "pipelines/commands/calibrate_camera_command.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "pipelines/measurement/board_views.h"
#include "tests/pipelines/scratch_directory.h"
#include "tests/vision/board_images.h"
#include "util/input_error.h"

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

  options.board = "7x5";  // the wrong board: too few views
  options.output_path = Path("camera_wrong.yaml");
  try {
    RunCalibrateCamera(options, out);
    FAIL() << "calibrated without boards";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fewer than 5; film it"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(options.output_path));
}

}  // namespace
}  // namespace softbench
