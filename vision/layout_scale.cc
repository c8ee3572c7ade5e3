#include "vision/layout_scale.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "vision/color_segmentation.h"
#include "vision/plane_mapping.h"

namespace softbench {
namespace {

double Sum(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum;
}

// Relative RMS misfit between two sorted distance lists after scaling the
// second onto the first.
double Misfit(const std::vector<double>& layout,
              const std::vector<double>& image) {
  const double scale = Sum(layout) / Sum(image);
  double sum_sq = 0.0;
  for (size_t i = 0; i < layout.size(); ++i) {
    sum_sq += std::pow(layout[i] - scale * image[i], 2);
  }
  return std::sqrt(sum_sq / layout.size()) / (Sum(layout) / layout.size());
}

}  // namespace

std::vector<double> PairDistances(const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> d;
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      d.push_back((points[i] - points[j]).norm());
    }
  }
  std::sort(d.begin(), d.end());
  return d;
}

LayoutScale MeasureLayoutScale(const FrameSource& frame,
                               const HeadMarkers& head,
                               const CameraIntrinsics& intrinsics,
                               const DotCentreOptions& centre_options) {
  LayoutScale result;
  if (head.dots < 2) {
    result.why_not = "a scale from dots needs a head with at least 2 dots";
    return result;
  }
  const cv::Mat bgr =
      frame.BgrRegion(cv::Rect(0, 0, frame.luma().cols, frame.luma().rows));
  cv::Mat mask = ColorMask(bgr, head.color);
  SegmentationOptions segmentation;
  segmentation.dot_radius_px = EstimateDotRadius(mask);
  if (segmentation.dot_radius_px < 1.5) {
    result.why_not = fmt::format("no {} dots at t = {:.3f} s", head.color_name,
                                 frame.time_s());
    return result;
  }
  CleanMask(segmentation, &mask);
  std::vector<Blob> blobs = FindBlobs(mask, segmentation).accepted;
  std::sort(blobs.begin(), blobs.end(), [](const Blob& a, const Blob& b) {
    return a.circularity > b.circularity;
  });
  if (blobs.size() > 12) blobs.resize(12);
  const int n = static_cast<int>(blobs.size()), k = head.dots;
  if (n < k) {
    result.why_not = fmt::format(
        "found {} {} dots at t = {:.3f} s, the plan "
        "says {}",
        n, head.color_name, frame.time_s(), k);
    return result;
  }
  // Image coordinates in pixels with the distortion removed.
  const PlaneMapping ideal = PlaneMapping::FromScale(intrinsics, 1.0, 0.0);
  const std::vector<double> layout = PairDistances(head.layout_mm);
  double best = std::numeric_limits<double>::infinity();
  std::vector<int> chosen;
  std::vector<bool> select(n, false);
  std::fill(select.begin(), select.begin() + k, true);
  do {
    std::vector<int> subset;
    std::vector<Eigen::Vector2d> points;
    for (int i = 0; i < n; ++i) {
      if (!select[i]) continue;
      subset.push_back(i);
      points.push_back(ideal.ToPlane(blobs[i].centroid));
    }
    const double misfit = Misfit(layout, PairDistances(points));
    if (misfit < best) {
      best = misfit;
      chosen = subset;
    }
  } while (std::prev_permutation(select.begin(), select.end()));
  std::vector<Eigen::Vector2d> refined;
  for (int i : chosen) {
    DotCentreOptions options = centre_options;
    options.luma_encoding = frame.luma_encoding();
    const DotCentre c = LocateDotCentre(frame.luma(), blobs[i].centroid,
                                        segmentation.dot_radius_px, options);
    if (!c.found) {
      result.why_not = "a dot's centre: " + c.why_not;
      return result;
    }
    refined.push_back(ideal.ToPlane(c.centre));
  }
  const std::vector<double> image = PairDistances(refined);
  result.misfit = Misfit(layout, image);
  if (result.misfit > 0.05) {
    result.why_not = fmt::format(
        "no {} of the {} {} dots are spaced like the plan's layout (best "
        "misfit {:.1f} %); check layout_mm",
        k, n, head.color_name, 100.0 * result.misfit);
    return result;
  }
  result.mm_per_px = Sum(layout) / Sum(image);
  result.found = true;
  return result;
}

}  // namespace softbench
