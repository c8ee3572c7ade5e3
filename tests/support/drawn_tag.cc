#include "tests/support/drawn_tag.h"

namespace softbench {

DrawnTag DrawTag(const TagBitmap& bitmap, int cell_px, cv::Size frame,
                 cv::Point origin) {
  DrawnTag tag;
  tag.luma = cv::Mat(frame, CV_8UC1, cv::Scalar(120));
  for (int row = 0; row < bitmap.total_width; ++row) {
    for (int col = 0; col < bitmap.total_width; ++col) {
      const cv::Rect cell(origin.x + col * cell_px, origin.y + row * cell_px,
                          cell_px, cell_px);
      tag.luma(cell & cv::Rect(cv::Point(), frame))
          .setTo(bitmap.IsWhite(row, col) ? 220 : 30);
    }
  }
  // Pixel centres at integers: a cell boundary at cell k lies at
  // origin + k * cell_px - 0.5. The printed tag's bottom-left first,
  // counter-clockwise (libapriltag's order).
  const double q = (bitmap.total_width - bitmap.width_at_border) / 2.0;
  const double e = q + bitmap.width_at_border;
  const auto at = [&](double x, double y) {
    return Eigen::Vector2d(origin.x + x * cell_px - 0.5,
                           origin.y + y * cell_px - 0.5);
  };
  tag.corners = {at(q, e), at(e, e), at(e, q), at(q, q)};
  return tag;
}

TestPlan TagSevenPlan() {
  return ParseTestPlan(R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 7, size_mm: 25}
tests:
  - {id: a, pressures: [6, 6, 0], actuate_s: 0.5, release_s: 2.5}
scene: {settle_time_constant_s: 0.1, rest_s: 1.0}
)",
                       "plan.yaml");
}

}  // namespace softbench
