#ifndef SOFTBENCH_PIPELINES_SYNTHETIC_PIXEL_GRID_H_
#define SOFTBENCH_PIPELINES_SYNTHETIC_PIXEL_GRID_H_

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

namespace softbench {

// Pixel coordinates to ideal normalised coordinates. With distortion, the
// normalised coordinates of every pixel corner are computed once (OpenCV's
// iterative undistortion, run to convergence) and subsamples interpolate
// bilinearly inside their pixel: the distortion's curvature over one pixel is
// below 1e-4 px for |k1| <= 0.3 at 4K.
struct PixelGrid {
  double fx, fy, cx, cy;
  int width = 0;
  std::vector<Eigen::Vector2d> corners;  // (height + 1) x (width + 1)

  Eigen::Vector2d At(double u, double v) const {
    if (corners.empty()) return {(u - cx) / fx, (v - cy) / fy};
    const double gx = u + 0.5, gy = v + 0.5;
    const int i = std::clamp(static_cast<int>(std::floor(gx)), 0, width - 1);
    const int rows = static_cast<int>(corners.size()) / (width + 1) - 1;
    const int j = std::clamp(static_cast<int>(std::floor(gy)), 0, rows - 1);
    const double a = gx - i, b = gy - j;
    const Eigen::Vector2d* row0 = &corners[j * (width + 1) + i];
    const Eigen::Vector2d* row1 = row0 + width + 1;
    return (1 - b) * ((1 - a) * row0[0] + a * row0[1]) +
           b * ((1 - a) * row1[0] + a * row1[1]);
  }
};

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_SYNTHETIC_PIXEL_GRID_H_
