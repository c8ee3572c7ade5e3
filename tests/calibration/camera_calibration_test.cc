// Camera calibration from rendered checkerboards with a known lens.
#include "calibration/camera_calibration.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "tests/vision/board_images.h"
#include "util/atomic_file.h"
#include "util/input_error.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

TEST(CameraCalibration, RecoversFocalLengthAndDistortion) {
  CameraIntrinsics truth =
      CameraIntrinsics::FromEquivalentFocalLength(52.0, 1920, 1080);
  truth.distortion[0] = -0.1;
  BoardOptions board{9, 6, 20.0};
  std::vector<std::vector<cv::Point2f>> corners;
  const BoardRenderer renderer(truth, 9, 6, 20.0);
  int seed = 1;
  for (const Camera& view : BoardViews(truth, 600.0)) {
    corners.push_back(
        FindBoardCorners(renderer.Render(view, 0.6, seed++), board));
  }
  const CameraCalibrationSummary summary =
      CalibrateCamera(corners, {1920, 1080}, {board, 5, false});
  ASSERT_TRUE(summary.converged) << summary.why_not;
  const CameraCalibration& c = summary.calibration;
  EXPECT_GE(c.views, 10);
  EXPECT_NEAR(c.camera_matrix(0, 0), truth.fx_px, 0.003 * truth.fx_px);
  EXPECT_NEAR(c.camera_matrix(0, 2), truth.cx_px, 3.0);
  EXPECT_NEAR(c.distortion[0], -0.1, 0.01);
  EXPECT_LT(c.reprojection_error_px, 0.1);
}

TEST(CameraCalibration, YamlRoundTripsThroughOpenCvFormat) {
  CameraCalibration c;
  c.width_px = 1920;
  c.height_px = 1080;
  c.camera_matrix = cv::Matx33d(2650.5, 0, 961.25, 0, 2651.5, 538.75, 0, 0, 1);
  c.distortion = {-0.1, 0.02, 1e-4, -2e-4, 0.0};
  c.reprojection_error_px = 0.042;
  c.views = 12;
  c.intrinsics_std_px = {1.5, 1.25, 0.75, 0.5};
  c.distortion_std = {0.002, 0.004, 1e-5, 2e-5, 0.0};
  const fs::path path = TestScratch().dir() / "softbench_camera.yaml";
  WriteFileAtomically(path.string(), CameraCalibrationToYaml(c));
  const CameraCalibration back = LoadCameraCalibration(path.string());
  EXPECT_EQ(back.width_px, 1920);
  EXPECT_EQ(back.height_px, 1080);
  for (int i = 0; i < 9; ++i)
    EXPECT_DOUBLE_EQ(back.camera_matrix.val[i], c.camera_matrix.val[i]);
  for (int i = 0; i < 5; ++i)
    EXPECT_DOUBLE_EQ(back.distortion[i], c.distortion[i]);
  EXPECT_DOUBLE_EQ(back.reprojection_error_px, 0.042);
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(back.intrinsics_std_px[i], c.intrinsics_std_px[i]);
  }
  for (int i = 0; i < 5; ++i) {
    EXPECT_DOUBLE_EQ(back.distortion_std[i], c.distortion_std[i]);
  }
  fs::remove(path);
}

// The standard errors are optional (OpenCV's own tools do not write them),
// but a negative one is refused with the file, the key and the value.
TEST(CameraCalibration, StandardErrorsAreOptionalAndNeverNegative) {
  const std::string base =
      "%YAML:1.0\n---\nimage_width: 1920\nimage_height: 1080\n"
      "camera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
      "  data: [2650., 0., 960., 0., 2650., 540., 0., 0., 1.]\n"
      "distortion_coefficients: !!opencv-matrix\n  rows: 1\n  cols: 5\n"
      "  dt: d\n  data: [-0.1, 0.02, 0., 0., 0.]\n";
  const fs::path path = TestScratch().dir() / "softbench_camera_std.yaml";
  WriteFileAtomically(path.string(), base);
  const CameraCalibration plain = LoadCameraCalibration(path.string());
  for (double s : plain.intrinsics_std_px) EXPECT_EQ(s, 0.0);
  for (double s : plain.distortion_std) EXPECT_EQ(s, 0.0);
  WriteFileAtomically(
      path.string(),
      base +
          "distortion_coefficients_std: !!opencv-matrix\n  rows: 1\n"
          "  cols: 5\n  dt: d\n  data: [0.002, -0.004, 0., 0., 0.]\n");
  const std::string message =
      InputErrorOf([&] { LoadCameraCalibration(path.string()); });
  EXPECT_NE(message.find("softbench_camera_std.yaml: "
                         "'distortion_coefficients_std' value 2 is -0.004"),
            std::string::npos)
      << message;
  fs::remove(path);
}

TEST(CameraCalibration, MissingKeyNamesFileAndKey) {
  const fs::path path = TestScratch().dir() / "softbench_camera_bad.yaml";
  WriteFileAtomically(
      path.string(), "%YAML:1.0\n---\nimage_width: 1920\nimage_height: 1080\n");
  const std::string message =
      InputErrorOf([&] { LoadCameraCalibration(path.string()); });
  EXPECT_NE(message.find("softbench_camera_bad.yaml: missing 'camera_matrix'"),
            std::string::npos)
      << message;
  fs::remove(path);
}

TEST(CameraCalibration, TooFewViewsSaysHowMany) {
  const CameraCalibrationSummary summary =
      CalibrateCamera({{}, {}}, {1920, 1080}, CameraCalibrationOptions{});
  EXPECT_FALSE(summary.converged);
  EXPECT_NE(summary.why_not.find("found in 0 views"), std::string::npos)
      << summary.why_not;
}

}  // namespace
}  // namespace softbench
