#include "vision/tag_detector.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "util/check.h"
#include "vision/color_transfer.h"
#include "vision/luma.h"

namespace softbench {

std::optional<std::string> TagDetectorOptions::Problem() const {
  if (!(edge_half_width_px >= 2.0)) return "edge_half_width_px must be >= 2";
  if (!(quad_decimate >= 1.0f)) return "quad_decimate must be >= 1";
  return std::nullopt;
}

namespace {

// The straight outer edge from corner a to corner b (black inside, white
// outside), located along it at sub-pixel accuracy. At each point the edge's
// offset along the normal comes from the integral of the profile across it:
//   offset = d - integral_{-d}^{d} (p(s) - black) ds / (white - black),
// which a symmetric blur (the lens, the pixel's area sampling,
// interpolation) does not change, unlike a threshold crossing. The profile
// is taken in linear light (options.luma_encoding): the blur mixes light,
// and integrated in codes a camera's transfer curve moves every edge toward
// the ink by a tenth of a pixel or so, shrinking the tag by ~0.35 %.
// Returns false when too few points had
// clean levels; `fit` (optional) receives how many of the points sampled
// were clean and the RMS distance of the edge points from the line.
struct EdgeFit {
  int sampled = 0, clean = 0;
  double rms_px = 0.0;
};
template <typename T>
bool FitEdgeOf(const cv::Mat& gray, const Eigen::Vector2d& a,
               const Eigen::Vector2d& b, const TagDetectorOptions& options,
               cv::Vec4f* line, EdgeFit* fit = nullptr) {
  const Eigen::Vector2d along = (b - a).normalized();
  // Outward normal: libapriltag's corners run counter-clockwise as seen on
  // screen, so with y down outward is (-along_y, along_x).
  const Eigen::Vector2d normal(-along.y(), along.x());
  const double d = options.edge_half_width_px, step = 0.25;
  const double length = (b - a).norm();
  std::vector<cv::Point2f> points;
  // One buffer for every profile: this runs for every frame's tag.
  std::vector<double> profile;
  profile.reserve(static_cast<size_t>(2 * d / step) + 2);
  const std::vector<float>& linear =
      LinearLumaTable(options.luma_encoding, cv::DataType<T>::depth);
  int sampled = 0;
  // Profiles every half pixel along the middle 60 % of the edge, at most
  // 160 (a 1080p tag's; a 4K tag's edge gets them a pixel apart, the same
  // spacing in millimetres): this runs for every frame.
  const double spacing = std::max(0.5, 0.6 * length / 160.0);
  for (double t = 0.2 * length; t <= 0.8 * length; t += spacing, ++sampled) {
    const Eigen::Vector2d p = a + t * along;
    profile.clear();
    for (double s = -d; s <= d + 1e-9; s += step) {
      const Eigen::Vector2d q = p + s * normal;
      profile.push_back(SampleLinearLuma<T>(gray, linear, q.x(), q.y()));
    }
    if (*std::min_element(profile.begin(), profile.end()) < 0) continue;
    // The contrast is judged in codes (40 levels of 255), as a person sees
    // it, so dim footage is refined as before.
    const Eigen::Vector2d inside = p - d * normal, outside = p + d * normal;
    if (SampleLuma<T>(gray, outside.x(), outside.y()) -
            SampleLuma<T>(gray, inside.x(), inside.y()) <
        40.0) {
      continue;
    }
    const int end = static_cast<int>(profile.size()) - 1;
    const int flat = static_cast<int>(1.0 / step);  // 1 px at each end
    double black = 0, white = 0;
    for (int i = 0; i <= flat; ++i) {
      black += profile[i] / (flat + 1);
      white += profile[end - i] / (flat + 1);
    }
    if (!(white > black)) continue;
    double integral = 0;  // trapezoid rule
    for (int i = 0; i < end; ++i) {
      integral += 0.5 * (profile[i] + profile[i + 1] - 2 * black) * step;
    }
    const double offset = d - integral / (white - black);
    const Eigen::Vector2d edge = p + offset * normal;
    points.emplace_back(static_cast<float>(edge.x()),
                        static_cast<float>(edge.y()));
  }
  if (points.size() < 8) return false;
  cv::fitLine(points, *line, cv::DIST_L2, 0, 1e-6, 1e-6);
  if (fit != nullptr) {
    double sum = 0.0;
    for (const cv::Point2f& q : points) {
      // Distance from the line through (x0, y0) along (vx, vy).
      const double d =
          ((*line)[0] * (q.y - (*line)[3]) - (*line)[1] * (q.x - (*line)[2]));
      sum += d * d;
    }
    *fit = {sampled, static_cast<int>(points.size()),
            std::sqrt(sum / points.size())};
  }
  return true;
}

// FitEdgeOf for 8 or 16-bit luma (vision/luma.h).
bool FitEdge(const cv::Mat& gray, const Eigen::Vector2d& a,
             const Eigen::Vector2d& b, const TagDetectorOptions& options,
             cv::Vec4f* line, EdgeFit* fit = nullptr) {
  return WithLumaType(gray, [&](auto type) {
    return FitEdgeOf<decltype(type)>(gray, a, b, options, line, fit);
  });
}

Eigen::Vector2d Intersect(const cv::Vec4f& l1, const cv::Vec4f& l2) {
  // Points p1 + s d1 = p2 + t d2.
  Eigen::Matrix2d m;
  m << l1[0], -l2[0], l1[1], -l2[1];
  const Eigen::Vector2d rhs(l2[2] - l1[2], l2[3] - l1[3]);
  const Eigen::Vector2d st = m.inverse() * rhs;
  return {l1[2] + st[0] * l1[0], l1[3] + st[0] * l1[1]};
}

}  // namespace

std::optional<std::array<Eigen::Vector2d, 4>> RefineTagCorners(
    const cv::Mat& gray, const std::array<Eigen::Vector2d, 4>& approximate,
    const TagDetectorOptions& options, double max_edge_rms_px) {
  std::array<cv::Vec4f, 4> edges;
  for (int c = 0; c < 4; ++c) {
    EdgeFit fit;
    // A covered or shadowed stretch leaves points out or bends the edge.
    if (!FitEdge(gray, approximate[c], approximate[(c + 1) % 4], options,
                 &edges[c], &fit) ||
        fit.clean < 0.9 * fit.sampled || fit.rms_px > max_edge_rms_px) {
      return std::nullopt;
    }
  }
  std::array<Eigen::Vector2d, 4> corners;
  for (int c = 0; c < 4; ++c) {
    corners[c] = Intersect(edges[(c + 3) % 4], edges[c]);
  }
  return corners;
}

struct TagDetector::Apriltag {
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  ~Apriltag() {
    apriltag_detector_destroy(detector);
    tag36h11_destroy(family);
  }
};

TagDetector::TagDetector(const TagDetectorOptions& options)
    : options_(options), apriltag_(std::make_unique<Apriltag>()) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  // Up to one corrected bit error: the two-bit table costs ~0.1 s to build,
  // and a tag big enough to measure by reads cleanly.
  apriltag_detector_add_family_bits(apriltag_->detector, apriltag_->family, 1);
  apriltag_->detector->quad_decimate = options.quad_decimate;
  apriltag_->detector->nthreads = 1;
}

TagDetector::~TagDetector() = default;

std::vector<TagDetection> TagDetector::Detect(const cv::Mat& gray) const {
  // libapriltag finds quads in 8 bits; the edges are fitted at full depth.
  const cv::Mat gray8 = LumaAs8Bit(gray);
  image_u8_t image{gray8.cols, gray8.rows, static_cast<int32_t>(gray8.step),
                   gray8.data};
  zarray_t* detections = apriltag_detector_detect(apriltag_->detector, &image);

  std::vector<TagDetection> tags;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(detections, i, &det);
    TagDetection tag;
    tag.id = det->id;
    tag.hamming = det->hamming;
    for (int c = 0; c < 4; ++c) {
      // libapriltag puts pixel centres at +0.5; OpenCV at integers.
      tag.coarse_corners[c] = {det->p[c][0] - 0.5, det->p[c][1] - 0.5};
    }
    std::array<cv::Vec4f, 4> edges;
    bool refined = true;
    for (int c = 0; c < 4 && refined; ++c) {
      refined = FitEdge(gray, tag.coarse_corners[c],
                        tag.coarse_corners[(c + 1) % 4], options_, &edges[c]);
    }
    for (int c = 0; c < 4; ++c) {
      tag.corners[c] = refined ? Intersect(edges[(c + 3) % 4], edges[c])
                               : tag.coarse_corners[c];
    }
    tag.refined = refined;
    tags.push_back(tag);
  }
  apriltag_detections_destroy(detections);
  return tags;
}

std::array<Eigen::Vector2d, 4> AverageTagCorners(
    const std::array<Eigen::Vector2d, 4>& reference,
    const std::vector<std::array<Eigen::Vector2d, 4>>& frames) {
  SOFTBENCH_CHECK(!frames.empty()) << "no frames to average";
  const auto centroid = [](const std::array<Eigen::Vector2d, 4>& corners) {
    return 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  };
  const Eigen::Vector2d to = centroid(reference);
  std::array<Eigen::Vector2d, 4> sum;
  sum.fill(Eigen::Vector2d::Zero());
  for (const std::array<Eigen::Vector2d, 4>& corners : frames) {
    // The rotation best taking the frame's corners (about their centroid)
    // onto the reference's: atan2 of the summed cross and dot products.
    const Eigen::Vector2d from = centroid(corners);
    double cross = 0.0, dot = 0.0;
    for (int c = 0; c < 4; ++c) {
      const Eigen::Vector2d a = corners[c] - from, b = reference[c] - to;
      cross += a.x() * b.y() - a.y() * b.x();
      dot += a.dot(b);
    }
    const Eigen::Rotation2Dd roll(std::atan2(cross, dot));
    for (int c = 0; c < 4; ++c) sum[c] += to + roll * (corners[c] - from);
  }
  for (Eigen::Vector2d& corner : sum)
    corner /= static_cast<double>(frames.size());
  return sum;
}

}  // namespace softbench
