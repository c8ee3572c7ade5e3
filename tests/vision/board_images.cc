#include "tests/vision/board_images.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace softbench {

BoardRenderer::BoardRenderer(const CameraIntrinsics& intrinsics, int corners_x,
                             int corners_y, double square_mm)
    : intrinsics_(intrinsics),
      corners_x_(corners_x),
      corners_y_(corners_y),
      square_mm_(square_mm) {
  // Ideal normalised coordinates of every pixel centre, in one batch.
  std::vector<cv::Point2d> pixels;
  pixels.reserve(static_cast<size_t>(intrinsics.width_px) *
                 intrinsics.height_px);
  for (int v = 0; v < intrinsics.height_px; ++v) {
    for (int u = 0; u < intrinsics.width_px; ++u) pixels.emplace_back(u, v);
  }
  const Camera camera(intrinsics, Eigen::Matrix3d::Identity(),
                      Eigen::Vector3d::Zero());
  normalized_ = camera.UndistortPixels(pixels);
}

cv::Mat BoardRenderer::Render(const Camera& camera, double noise_dn,
                              int seed) const {
  const int w = intrinsics_.width_px, h = intrinsics_.height_px;
  const double square_mm = square_mm_;
  const std::vector<Eigen::Vector2d>& normalized = normalized_;
  const Eigen::Matrix3d board_from_normalized =
      camera.NormalizedFromPlane(0.0).inverse();
  // Board coordinates in squares, origin at the outer corner of the squares.
  const double squares_x = corners_x_ + 1, squares_y = corners_y_ + 1;
  cv::Mat_<cv::Vec2d> board(h, w);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3d q =
          board_from_normalized *
          normalized[static_cast<size_t>(v) * w + u].homogeneous();
      board(v, u) = cv::Vec2d(q.x() / q.z() / square_mm + squares_x / 2,
                              q.y() / q.z() / square_mm + squares_y / 2);
    }
  }
  // A square wave box-filtered over a footprint of `width` squares.
  const auto wave = [](double f, double width) {
    const double cell = std::floor(f);
    const double sign = static_cast<int64_t>(cell) % 2 == 0 ? 1.0 : -1.0;
    const double to_line = std::min(f - cell, cell + 1 - f);
    return sign * std::min(1.0, 2.0 * to_line / std::max(width, 1e-9));
  };
  cv::Mat image(h, w, CV_8UC1);
  cv::RNG rng(seed);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const cv::Vec2d p = board(v, u);
      const cv::Vec2d du =
          board(v, std::min(u + 1, w - 1)) - board(v, std::max(u - 1, 0));
      const cv::Vec2d dv =
          board(std::min(v + 1, h - 1), u) - board(std::max(v - 1, 0), u);
      const double wx = 0.5 * (std::abs(du[0]) + std::abs(dv[0]));
      const double wy = 0.5 * (std::abs(du[1]) + std::abs(dv[1]));
      double value = 0.45;  // grey table around the board
      if (p[0] >= -1 && p[0] < squares_x + 1 && p[1] >= -1 &&
          p[1] < squares_y + 1) {
        value = 1.0;  // white margin
        if (p[0] >= 0 && p[0] < squares_x && p[1] >= 0 && p[1] < squares_y) {
          value = 0.5 + 0.5 * wave(p[0], wx) * wave(p[1], wy);
        }
      }
      const double level = 25.0 + 205.0 * value + rng.gaussian(noise_dn);
      image.at<uint8_t>(v, u) =
          static_cast<uint8_t>(std::clamp(std::lround(level), 0L, 255L));
    }
  }
  return image;
}

std::vector<Camera> BoardViews(const CameraIntrinsics& intrinsics,
                               double distance_mm) {
  const double deg = std::numbers::pi / 180.0;
  std::vector<Camera> views;
  const double offsets[][2] = {{0, 0},   {-70, -40}, {70, -40}, {-70, 40},
                               {70, 40}, {0, -50},   {0, 50},   {-80, 0},
                               {80, 0},  {-40, 20},  {40, -20}, {20, 35}};
  const double tilts[][2] = {{0, 0},     {15, 10}, {-15, 10}, {12, -14},
                             {-10, -12}, {20, 0},  {-20, 0},  {0, 20},
                             {0, -20},   {8, 18},  {-18, -8}, {10, -5}};
  for (size_t i = 0; i < std::size(offsets); ++i) {
    views.push_back(Camera::LookingDown(
        intrinsics, Eigen::Vector3d(offsets[i][0], offsets[i][1], 0.0),
        distance_mm, tilts[i][0] * deg, tilts[i][1] * deg));
  }
  return views;
}

}  // namespace softbench
