#ifndef SOFTBENCH_CALIBRATION_CAMERA_CALIBRATION_H_
#define SOFTBENCH_CALIBRATION_CAMERA_CALIBRATION_H_

#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace softbench {

// A camera's intrinsics and distortion as OpenCV's calibration writes them
// (camera_matrix, distortion_coefficients k1 k2 p1 p2 k3).
struct CameraCalibration {
  int width_px = 0;
  int height_px = 0;
  cv::Matx33d camera_matrix = cv::Matx33d::eye();
  std::array<double, 5> distortion{};
  double reprojection_error_px = 0.0;  // RMS over every corner
  int views = 0;                       // images the fit used
  // RMS reprojection error of each view the fit used, in the order given
  // (a view far above the others is a blurred or misdetected board).
  std::vector<double> view_errors_px;
  // Standard errors of fx, fy, cx, cy [px] and of k1 k2 p1 p2 k3 (0 for a
  // coefficient held fixed), from the fit's covariance.
  std::array<double, 4> intrinsics_std_px{};
  std::array<double, 5> distortion_std{};
};

struct BoardOptions {
  // Inner corners per row and column of the checkerboard (OpenCV's
  // pattern size), and the side of one square [mm].
  int corners_x = 9;
  int corners_y = 6;
  double square_mm = 10.0;

  std::optional<std::string> Problem() const;
};

// The board's inner corners in one grey image (8 or 16-bit), refined to
// sub-pixel (cornerSubPix); empty when the whole board is not found.
std::vector<cv::Point2f> FindBoardCorners(const cv::Mat& gray,
                                          const BoardOptions& options);

// The inner corners (columns x rows, in the image's own orientation) of the
// checkerboard in `gray` whatever its size: OpenCV's sector-based detector
// allowed to find a board larger than 4 x 3. nullopt when none is seen. Used
// to tell a user which --board the print has; one view can over- or
// under-count by a row, so callers take the most common answer of several.
std::optional<cv::Size> CountBoardCorners(const cv::Mat& gray);

// The same board either way round (9 x 6 is 6 x 9 turned).
inline bool SameBoardSize(const cv::Size& a, const cv::Size& b) {
  return a == b || (a.width == b.height && a.height == b.width);
}

struct CameraCalibrationOptions {
  BoardOptions board;
  // Fewest views with a detected board for a fit (OpenCV needs 3 to
  // separate focal length from pose; more views pin distortion down).
  int min_views = 5;
  // Estimate k3 too; off by default as for moderate lenses it trades with
  // k1/k2 and overfits.
  bool fit_k3 = false;

  std::optional<std::string> Problem() const;
};

struct CameraCalibrationSummary {
  bool converged = false;
  std::string why_not;  // when !converged
  CameraCalibration calibration;
};

// Zhang's method (cv::calibrateCamera) over the boards found in `views`
// (grey images of one size).
CameraCalibrationSummary CalibrateCamera(
    const std::vector<std::vector<cv::Point2f>>& corners_per_view,
    const cv::Size& image_size, const CameraCalibrationOptions& options);

// OpenCV FileStorage YAML (readable by OpenCV's own tools).
std::string CameraCalibrationToYaml(const CameraCalibration& calibration);
// Reads such a file; throws InputError naming the file and the missing or
// malformed key.
CameraCalibration LoadCameraCalibration(const std::string& path);

}  // namespace softbench

#endif  // SOFTBENCH_CALIBRATION_CAMERA_CALIBRATION_H_
