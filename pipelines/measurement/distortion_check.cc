#include "pipelines/measurement/distortion_check.h"

#include <fmt/format.h>

#include <cmath>

#include "util/statistics.h"
#include "vision/layout_scale.h"

namespace softbench {
namespace {

double MeanPairDistance(const std::vector<Eigen::Vector2d>& points) {
  const std::vector<double> d = PairDistances(points);
  double sum = 0.0;
  for (double v : d) sum += v;
  return d.empty() ? 0.0 : sum / d.size();
}

}  // namespace

DistortionCheck CheckDistortion(const TestPlan& plan,
                                const std::vector<FrameSample>& frames,
                                const std::string& scale_source) {
  DistortionCheck check;
  check.tolerance = plan.calibration.distortion_tolerance;
  std::vector<double> ratios;
  for (const FrameSample& f : frames) {
    for (size_t h = 0; h < f.heads.size(); ++h) {
      const HeadObservation& obs = f.heads[h].observation;
      const double nominal = MeanPairDistance(plan.markers[h].layout_mm);
      if (!obs.complete || nominal <= 0.0) continue;
      std::vector<Eigen::Vector2d> dots;
      for (const DotObservation& d : obs.dots) dots.push_back(d.plane_mm);
      ratios.push_back(MeanPairDistance(dots) / nominal);
    }
  }
  if (ratios.empty()) return check;
  check.performed = true;
  check.median_ratio = Median(ratios);
  // The 5th..95th percentiles: frames in mid-motion (blur) are not the lens.
  check.min_ratio = Quantile(ratios, 0.05);
  check.max_ratio = Quantile(ratios, 0.95);
  const double offset = std::abs(check.median_ratio - 1.0);
  const double spread = check.max_ratio - check.min_ratio;
  check.warn = offset > check.tolerance || spread > check.tolerance;
  check.message = fmt::format(
      "dot spacing measured through the {} scale is {:+.3f} % of the plan's "
      "layout (5-95 % range {:.3f} % over the video; tolerance {:.3f} %)",
      scale_source, 100.0 * (check.median_ratio - 1.0), 100.0 * spread,
      100.0 * check.tolerance);
  if (check.warn) {
    check.message +=
        "; the scale differs across the field: calibrate the lens "
        "(softbench calibrate-camera) and set calibration.intrinsics, or "
        "check layout_mm against the printed dots";
  }
  return check;
}

}  // namespace softbench
