#include "pipelines/measurement/span_measurer.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "pipelines/measurement/plan_camera.h"
#include "vision/tag_detector.h"

namespace softbench {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// Outside the mechanism: the hull of its fixed anchors and heads at rest,
// grown by 14 mm (the bellows' 11 mm half width where they meet the
// anchors, and the heads' travel), is where things move; the ring and the
// mounts outside it stay. The mapping's origin is its tag's (or
// the image centre's), not the mechanism's: the heads found in `first`
// place the mechanism's frame on the plane (the axes are the same).
cv::Mat StaticMask(const TestPlan& plan, const PlaneMapping& mapping,
                   const FrameSource& first) {
  HeadTracker tracker(mapping, PlanHeadMarkers(plan));
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
  int heads = 0;
  const std::vector<HeadObservation> found = tracker.Measure(first);
  for (size_t h = 0; h < found.size(); ++h) {
    if (!found[h].position_mm.allFinite()) continue;
    offset += found[h].position_mm -
              plan.mechanism.heads[plan.markers[h].head].rest_mm;
    ++heads;
  }
  const cv::Size size = first.luma().size();
  // Without a head in view the first frame fails later with its own
  // message; no patch is taken meanwhile.
  if (heads == 0) return {size, CV_8UC1, cv::Scalar(0)};
  offset /= heads;
  std::vector<cv::Point> outline;
  const auto add = [&](const Eigen::Vector2d& mm) {
    const Eigen::Vector2d px = mapping.ToPixel(mm + offset);
    outline.emplace_back(cvRound(px.x()), cvRound(px.y()));
  };
  for (const FixedAnchor& a : plan.mechanism.fixed_anchors) add(a.position_mm);
  for (const Head& h : plan.mechanism.heads) add(h.rest_mm);
  std::vector<cv::Point> hull;
  cv::convexHull(outline, hull);
  // Grown by 14 mm: a convex polygon grown by a disc is the hull of discs
  // at its corners (a dilation of the image with a 60 px disc cost more than
  // measuring 50 frames).
  const Eigen::Vector2d centre(size.width / 2.0, size.height / 2.0);
  const double grow = 14.0 / mapping.MmPerPixelAt(centre);
  std::vector<cv::Point> grown;
  for (const cv::Point& corner : hull) {
    for (int k = 0; k < 64; ++k) {
      const double angle = 2.0 * M_PI * k / 64;
      grown.emplace_back(cvRound(corner.x + grow * std::cos(angle)),
                         cvRound(corner.y + grow * std::sin(angle)));
    }
  }
  cv::convexHull(grown, hull);
  cv::Mat still(size, CV_8UC1, cv::Scalar(255));
  cv::fillConvexPoly(still, hull, cv::Scalar(0));
  return still;
}

}  // namespace

HeadObservation Unmeasured(int dots, const std::string& why) {
  HeadObservation obs;
  obs.dots.assign(dots, DotObservation{});
  obs.position_mm = obs.pixel = obs.binary_position_mm =
      Eigen::Vector2d(kNan, kNan);
  obs.note = why;
  return obs;
}

RegistrationReference MakeRegistrationReference(
    const TestPlan& plan, const FrameSource& first, const PlaneMapping& mapping,
    const std::optional<std::array<Eigen::Vector2d, 4>>& tag_corners) {
  RegistrationReference reference;
  reference.static_mask = StaticMask(plan, mapping, first);
  if (tag_corners) {
    TagReference& tag = reference.tag.emplace();
    tag.id = plan.calibration.tag->id;
    TagDetectorOptions options;
    options.luma_encoding = first.luma_encoding();
    tag.corners = RefineTagCorners(first.luma(), *tag_corners, options, 0.25)
                      .value_or(*tag_corners);
  }
  return reference;
}

}  // namespace softbench
