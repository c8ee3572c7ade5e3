#include "pipelines/measurement/distortion_check.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "util/statistics.h"

namespace softbench {
namespace {

// The distances between `points` in pair order (0-1, 0-2, ..., 1-2, ...):
// the dots follow their layout's order, so pair k is the same pair in the
// layout and in every frame.
std::vector<double> OrderedPairDistances(
    const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> d;
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      d.push_back((points[i] - points[j]).norm());
    }
  }
  return d;
}

double Mean(const std::vector<double>& values) {
  return values.empty() ? 0.0
                        : std::accumulate(values.begin(), values.end(), 0.0) /
                              static_cast<double>(values.size());
}

// The distances over their mean.
std::vector<double> Shape(std::vector<double> distances) {
  const double mean = Mean(distances);
  for (double& d : distances) d /= mean;
  return distances;
}

// Why the dots' spacing and the tag disagree, and what is done about it,
// for a check that warns.
std::string Cause(const TestPlan& plan, const DistortionCheck& check,
                  double spread, const std::string& scale_source,
                  const CameraProcessing& processing) {
  const double offset = check.median_ratio - 1.0;
  const std::string kept = fmt::format(
      "the {} scale is kept, and the difference is carried in every "
      "change's uncertainty (its scale term)",
      scale_source);
  // A misfit below half the tolerance is not the layout's, whatever made
  // the check warn (a lens's spread with no offset at all).
  if (check.shape_head >= 0 &&
      check.shape_misfit >= 0.5 * std::max(std::abs(offset), check.tolerance)) {
    return fmt::format(
        "; the dots of head '{}' misfit the layout's shape by {:.3f} %, as "
        "much as the scale disagrees: layout_mm does not describe the printed "
        "dots, so it cannot check the scale; {}; measure the printed dots "
        "and correct layout_mm",
        plan.mechanism.heads[check.shape_head].name, 100.0 * check.shape_misfit,
        kept);
  }
  const bool lens_unknown = plan.calibration.intrinsics_path.empty();
  if (spread > check.tolerance) {
    return fmt::format(
        "; the scale differs across the field: {}; {}",
        lens_unknown
            ? "calibrate the lens (softbench calibrate-camera) and set "
              "calibration.intrinsics"
            : "calibrate the lens again (softbench calibrate-camera)",
        kept);
  }
  std::vector<std::string> causes;
  if (lens_unknown) {
    causes.emplace_back(
        "the lens, uncalibrated (the tag and the heads in different parts of "
        "the field: softbench calibrate-camera, then "
        "calibration.intrinsics)");
  }
  if (std::isfinite(check.implied_plane_offset_mm)) {
    causes.emplace_back(fmt::format(
        "the dots' height above the tag (they measure as if {:.1f} mm, "
        "where calibration.plane_offset_mm says {:g})",
        check.implied_plane_offset_mm, plan.calibration.plane_offset_mm));
  }
  if (plan.calibration.tag) {
    causes.emplace_back(fmt::format(
        "the tag's printed size (as if {:.2f} mm, where size_mm says {:g})",
        plan.calibration.tag->size_mm / check.median_ratio,
        plan.calibration.tag->size_mm));
  }
  causes.emplace_back("the dots' printed spacing (layout_mm)");
  const std::string shape =
      check.shape_head >= 0
          ? fmt::format("the dots' shape matches the layout (to {:.3f} %)",
                        100.0 * check.shape_misfit)
          : "the dots (two per head) cannot show whether the layout is "
            "theirs";
  if (processing.tag_scale_at_risk && plan.calibration.tag) {
    // The tag's border shows processing that moves small cells' midlines
    // (CameraProcessingOptions::min_cell_px): the likeliest cause.
    return fmt::format(
        "; {}, and the scale is off alike over the video: most likely the "
        "tag's, as the camera's sharpening or tone curve (seen on its "
        "border) moves the scale of a tag whose cells are {:.1f} px by as "
        "much as 0.6 %; print the tag at least {:.0f} mm across, or "
        "film it closer, so that its cells are {:.0f} px or more; else one "
        "of: {}; {}",
        shape, processing.tag_cell_px,
        std::ceil(plan.calibration.tag->size_mm *
                  processing.tag_cells_wanted_px / processing.tag_cell_px),
        processing.tag_cells_wanted_px, fmt::join(causes, "; "), kept);
  }
  return fmt::format(
      "; {}, and the scale is off alike over the video, which the footage "
      "cannot trace to one of: {}; {}; measure them and correct the plan",
      shape, fmt::join(causes, "; "), kept);
}

}  // namespace

DistortionCheck CheckDistortion(const TestPlan& plan,
                                const std::vector<FrameSample>& frames,
                                const std::string& scale_source,
                                double camera_height_mm,
                                const CameraProcessing& processing) {
  DistortionCheck check;
  check.tolerance = plan.calibration.distortion_tolerance;
  const size_t heads = plan.markers.size();
  std::vector<std::vector<double>> layouts;  // per head, its pairs' [mm]
  for (const MarkerSpec& marker : plan.markers) {
    layouts.push_back(OrderedPairDistances(marker.layout_mm));
  }
  std::vector<double> ratios;
  // Per head and pair, the pair's share of each frame's distances (Shape).
  std::vector<std::vector<std::vector<double>>> shapes(heads);
  for (const FrameSample& f : frames) {
    for (size_t h = 0; h < f.heads.size() && h < heads; ++h) {
      const HeadObservation& obs = f.heads[h].observation;
      const std::vector<double>& layout = layouts[h];
      const double nominal = Mean(layout);
      if (!obs.complete || !(nominal > 0.0)) continue;
      std::vector<Eigen::Vector2d> dots;
      for (const DotObservation& d : obs.dots) dots.push_back(d.plane_mm);
      const std::vector<double> measured = OrderedPairDistances(dots);
      if (measured.size() != layout.size()) continue;
      ratios.push_back(Mean(measured) / nominal);
      const std::vector<double> shape = Shape(measured);
      shapes[h].resize(shape.size());
      for (size_t k = 0; k < shape.size(); ++k) {
        shapes[h][k].push_back(shape[k]);
      }
    }
  }
  if (ratios.empty()) return check;
  check.performed = true;
  check.median_ratio = Median(ratios);
  // The 5th..95th percentiles: frames in mid-motion (blur) are not the lens.
  check.min_ratio = Quantile(ratios, 0.05);
  check.max_ratio = Quantile(ratios, 0.95);
  // Two dots have one distance, and no shape to check.
  for (size_t h = 0; h < heads; ++h) {
    if (shapes[h].size() < 3) continue;
    const std::vector<double> layout = Shape(layouts[h]);
    double squares = 0.0;
    for (size_t k = 0; k < layout.size(); ++k) {
      squares += std::pow(Median(shapes[h][k]) - layout[k], 2);
    }
    const double misfit = std::sqrt(squares / layout.size());
    if (check.shape_head < 0 || misfit > check.shape_misfit) {
      check.shape_misfit = misfit;
      check.shape_head = static_cast<int>(h);
    }
  }
  // Dots that look r times their layout's size through a mapping at the
  // plan's height are 1/r times as far from the camera.
  if (camera_height_mm > 0.0) {
    const double dots_from_camera_mm =
        camera_height_mm - plan.calibration.plane_offset_mm;
    check.implied_plane_offset_mm =
        camera_height_mm - dots_from_camera_mm / check.median_ratio;
  }
  const double offset = std::abs(check.median_ratio - 1.0);
  const double spread = check.max_ratio - check.min_ratio;
  check.warn = offset > check.tolerance || spread > check.tolerance;
  check.message = fmt::format(
      "dot spacing measured through the {} scale is {:+.3f} % of the plan's "
      "layout (5-95 % range {:.3f} % over the video; tolerance {:.3f} %)",
      scale_source, 100.0 * (check.median_ratio - 1.0), 100.0 * spread,
      100.0 * check.tolerance);
  if (check.warn) {
    check.message += Cause(plan, check, spread, scale_source, processing);
  }
  return check;
}

}  // namespace softbench
