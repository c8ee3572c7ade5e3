#include "calibration/camera_calibration.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "util/input_error.h"
#include "util/text_file.h"

namespace softbench {

// An OpenCV intrinsics file is under a kilobyte.
constexpr int64_t kMaxIntrinsicsBytes = int64_t{1} << 20;

std::optional<std::string> BoardOptions::Problem() const {
  if (corners_x < 3 || corners_y < 3) {
    return "the board needs at least 3 x 3 inner corners";
  }
  if (corners_x == corners_y) {
    return "use a board with different corner counts per side (e.g. 9 x 6), "
           "so its orientation is unambiguous";
  }
  if (!(square_mm > 0.0)) return "the square size must be > 0 mm";
  return std::nullopt;
}

std::optional<std::string> CameraCalibrationOptions::Problem() const {
  if (auto problem = board.Problem()) return problem;
  if (min_views < 3) return "min_views must be >= 3";
  return std::nullopt;
}

std::vector<cv::Point2f> FindBoardCorners(const cv::Mat& gray,
                                          const BoardOptions& options) {
  std::vector<cv::Point2f> corners;
  const cv::Size pattern(options.corners_x, options.corners_y);
  // FAST_CHECK turns away a view without a board in milliseconds (a
  // video of anything else would otherwise take minutes). OpenCV finds the
  // board in 8 bits; deeper luma (10 and 12-bit video, scaled to fill 16
  // bits: LumaFilling16Bits) is refined at its full precision.
  cv::Mat gray8 = gray, fine = gray;
  if (gray.depth() == CV_16U) {
    gray.convertTo(gray8, CV_8U, 1.0 / 256.0);
    gray.convertTo(fine, CV_32F, 1.0 / 256.0);
  }
  if (!cv::findChessboardCorners(gray8, pattern, corners,
                                 cv::CALIB_CB_ADAPTIVE_THRESH |
                                     cv::CALIB_CB_NORMALIZE_IMAGE |
                                     cv::CALIB_CB_FAST_CHECK)) {
    return {};
  }
  cv::cornerSubPix(
      fine, corners, cv::Size(5, 5), cv::Size(-1, -1),
      cv::TermCriteria(cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 100,
                       1e-4));
  return corners;
}

std::optional<cv::Size> CountBoardCorners(const cv::Mat& gray) {
  cv::Mat gray8 = gray;
  if (gray.depth() == CV_16U) gray.convertTo(gray8, CV_8U, 1.0 / 256.0);
  std::vector<cv::Point2f> corners;
  cv::Mat meta;
  // The smallest pattern that is not square: with CALIB_CB_LARGER the
  // detector grows it to the whole board and `meta` takes the board's size.
  if (!cv::findChessboardCornersSB(gray8, cv::Size(4, 3), corners,
                                   cv::CALIB_CB_LARGER, meta) ||
      meta.empty()) {
    return std::nullopt;
  }
  return cv::Size(meta.cols, meta.rows);
}

CameraCalibrationSummary CalibrateCamera(
    const std::vector<std::vector<cv::Point2f>>& corners_per_view,
    const cv::Size& image_size, const CameraCalibrationOptions& options) {
  CameraCalibrationSummary summary;
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  std::vector<cv::Point3f> board;
  for (int y = 0; y < options.board.corners_y; ++y) {
    for (int x = 0; x < options.board.corners_x; ++x) {
      board.emplace_back(static_cast<float>(x * options.board.square_mm),
                         static_cast<float>(y * options.board.square_mm), 0.f);
    }
  }
  for (const auto& corners : corners_per_view) {
    if (corners.size() != board.size()) continue;
    object_points.push_back(board);
    image_points.push_back(corners);
  }
  const int views = static_cast<int>(image_points.size());
  if (views < options.min_views) {
    summary.why_not = fmt::format(
        "the board ({} x {} inner corners) was found in {} view{}, fewer "
        "than {}; film it from more angles or check --board",
        options.board.corners_x, options.board.corners_y, views,
        views == 1 ? "" : "s", options.min_views);
    return summary;
  }
  cv::Mat camera_matrix, distortion, intrinsics_std, extrinsics_std,
      view_errors;
  std::vector<cv::Mat> rvecs, tvecs;
  const int flags = options.fit_k3 ? 0 : cv::CALIB_FIX_K3;
  const double rms = cv::calibrateCamera(
      object_points, image_points, image_size, camera_matrix, distortion, rvecs,
      tvecs, intrinsics_std, extrinsics_std, view_errors, flags,
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200,
                       1e-12));
  CameraCalibration& c = summary.calibration;
  c.width_px = image_size.width;
  c.height_px = image_size.height;
  c.camera_matrix = static_cast<cv::Matx33d>(camera_matrix);
  for (int i = 0; i < 5; ++i) c.distortion[i] = distortion.at<double>(i);
  c.reprojection_error_px = rms;
  c.views = views;
  // OpenCV's order: fx fy cx cy k1 k2 p1 p2 k3 ...
  for (int i = 0; i < 4; ++i)
    c.intrinsics_std_px[i] = intrinsics_std.at<double>(i);
  for (int i = 0; i < 5; ++i)
    c.distortion_std[i] = intrinsics_std.at<double>(4 + i);
  for (int v = 0; v < view_errors.rows; ++v) {
    c.view_errors_px.push_back(view_errors.at<double>(v));
  }
  summary.converged = std::isfinite(rms);
  if (!summary.converged) summary.why_not = "the fit diverged";
  return summary;
}

std::string CameraCalibrationToYaml(const CameraCalibration& calibration) {
  cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY |
                                  cv::FileStorage::FORMAT_YAML);
  fs << "image_width" << calibration.width_px;
  fs << "image_height" << calibration.height_px;
  fs << "camera_matrix" << cv::Mat(calibration.camera_matrix);
  fs << "distortion_coefficients"
     << cv::Mat(1, 5, CV_64F,
                const_cast<double*>(calibration.distortion.data()));
  fs << "avg_reprojection_error" << calibration.reprojection_error_px;
  fs << "views" << calibration.views;
  // As OpenCV's calibration sample names them; read by people, not by
  // LoadCameraCalibration.
  if (!calibration.view_errors_px.empty()) {
    fs << "per_view_reprojection_errors"
       << cv::Mat(calibration.view_errors_px, true);
  }
  fs << "intrinsics_std_px_fx_fy_cx_cy"
     << cv::Mat(1, 4, CV_64F,
                const_cast<double*>(calibration.intrinsics_std_px.data()));
  fs << "distortion_coefficients_std"
     << cv::Mat(1, 5, CV_64F,
                const_cast<double*>(calibration.distortion_std.data()));
  return fs.releaseAndGetString();
}

CameraCalibration LoadCameraCalibration(const std::string& path) {
  const std::string text =
      ReadTextFile(path, "intrinsics file", kMaxIntrinsicsBytes);
  cv::FileStorage fs;
  try {
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": not an OpenCV YAML/XML file (" + e.err +
                     "); write it with softbench calibrate-camera");
  }
  const auto require = [&](const char* key) {
    const cv::FileNode node = fs[key];
    if (node.empty()) {
      throw InputError(path + ": missing '" + key +
                       "'; write the file with softbench calibrate-camera");
    }
    return node;
  };
  CameraCalibration c;
  c.width_px = static_cast<int>(require("image_width"));
  c.height_px = static_cast<int>(require("image_height"));
  cv::Mat matrix, distortion;
  require("camera_matrix") >> matrix;
  require("distortion_coefficients") >> distortion;
  if (matrix.rows != 3 || matrix.cols != 3 || distortion.total() < 4 ||
      distortion.total() > 5 || c.width_px <= 0 || c.height_px <= 0) {
    throw InputError(path +
                     ": camera_matrix must be 3x3, distortion_coefficients "
                     "4 or 5 values, image sizes positive");
  }
  matrix.convertTo(matrix, CV_64F);
  distortion.convertTo(distortion, CV_64F);
  c.camera_matrix = static_cast<cv::Matx33d>(matrix);
  for (size_t i = 0; i < distortion.total(); ++i) {
    c.distortion[i] = distortion.at<double>(static_cast<int>(i));
  }
  if (const cv::FileNode error = fs["avg_reprojection_error"]; !error.empty())
    c.reprojection_error_px = static_cast<double>(error);
  // The standard errors, where the file has them (OpenCV's own tools do not
  // write them): without, the budget has no intrinsics term.
  const auto read_std = [&](const char* key, size_t min_size, double* out,
                            size_t size) {
    const cv::FileNode node = fs[key];
    if (node.empty()) return;
    cv::Mat values;
    node >> values;
    if (values.empty() || values.total() < min_size || values.total() > size) {
      throw InputError(fmt::format(
          "{}: '{}' must have {} values; write the file with softbench "
          "calibrate-camera",
          path, key,
          min_size == size ? fmt::format("{}", size)
                           : fmt::format("{} to {}", min_size, size)));
    }
    values.convertTo(values, CV_64F);
    for (size_t i = 0; i < values.total(); ++i) {
      out[i] = values.at<double>(static_cast<int>(i));
      if (!std::isfinite(out[i]) || out[i] < 0.0) {
        throw InputError(fmt::format(
            "{}: '{}' value {} is {}; standard errors are finite and >= 0",
            path, key, i + 1, out[i]));
      }
    }
  };
  read_std("intrinsics_std_px_fx_fy_cx_cy", 4, c.intrinsics_std_px.data(), 4);
  read_std("distortion_coefficients_std", 4, c.distortion_std.data(), 5);
  return c;
}

}  // namespace softbench
