#include "pipelines/synthetic/scene_renderer.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "model/units.h"
#include "pipelines/formats/dot_colors.h"
#include "pipelines/synthetic/pixel_grid.h"
#include "util/input_error.h"
#include "vision/color_transfer.h"
#include "vision/tag_bitmap.h"

namespace softbench {
namespace {

// Linear light (8-bit levels) of BT.709 codes (8-bit levels). The scene's
// colours are given as a camera shows them, so flat areas keep these codes
// under even light; they are composed, blurred, moved and lit in light, as
// a lens and sensor do, and encoded with the BT.709 curve only at the end.
cv::Vec3f LinearLevels(const cv::Vec3f& code) {
  cv::Vec3f light;
  for (int c = 0; c < 3; ++c) {
    light[c] =
        static_cast<float>(255.0 * ToLinear(Transfer::kSdr, code[c] / 255.0));
  }
  return light;
}

// Layer colours (BGR, linear light from 8-bit codes). Clear resin heads and
// ring, pale bellows, a grey-brown table, white paper and black ink for the
// tag.
const cv::Vec3f kRingColor = LinearLevels({196, 200, 202});
const cv::Vec3f kHeadColor = LinearLevels({214, 217, 220});
const cv::Vec3f kBellowsColor = LinearLevels({176, 186, 196});
const cv::Vec3f kTableCode(92, 108, 124);
const cv::Vec3f kPaperColor = LinearLevels({236, 238, 238});
const cv::Vec3f kInkColor = LinearLevels({22, 22, 24});
const cv::Vec3f kGlintColor = LinearLevels({255, 255, 255});

bool InPolygon(const std::vector<Eigen::Vector2d>& ccw,
               const Eigen::Vector2d& p) {
  for (size_t i = 0; i < ccw.size(); ++i) {
    const Eigen::Vector2d e = ccw[(i + 1) % ccw.size()] - ccw[i];
    const Eigen::Vector2d d = p - ccw[i];
    if (e.x() * d.y() - e.y() * d.x() < 0.0) return false;
  }
  return true;
}

// Pixels around the projections of plane points at `height`, with a margin
// for anti-aliasing; the points must enclose the shape (projection maps
// lines to lines, so the shape's image stays inside theirs).
cv::Rect ImageBox(const Camera& camera,
                  const std::vector<Eigen::Vector2d>& points, double height) {
  std::vector<cv::Point2f> projected;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d q =
        camera.Project(Eigen::Vector3d(p.x(), p.y(), height));
    projected.emplace_back(static_cast<float>(q.x()),
                           static_cast<float>(q.y()));
  }
  const cv::Rect r = cv::boundingRect(projected);
  return {r.x - 3, r.y - 3, r.width + 6, r.height + 6};
}

double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

}  // namespace

cv::Vec3f MarkerColorBgr(const std::string& name) {
  const DotColor* color = FindDotColor(name);
  if (color == nullptr) {
    throw InputError("marker colour '" + name + "' is not " + DotColorNames());
  }
  return LinearLevels({static_cast<float>(color->ink_bgr[0]),
                       static_cast<float>(color->ink_bgr[1]),
                       static_cast<float>(color->ink_bgr[2])});
}

std::optional<std::string> RenderOptions::Problem() const {
  if (auto problem = intrinsics.Problem()) return problem;
  if (!(distance_mm > 50.0 && distance_mm <= 10000.0)) {
    return "camera distance must be > 50 mm and at most 10 m";
  }
  if (std::abs(tilt_x_deg) > 30.0 || std::abs(tilt_y_deg) > 30.0) {
    return "tilt must be within +-30 deg";
  }
  if (sensor_scale < 1 || sensor_scale > 4) {
    return "the sensor's scale must be 1..4 sensor pixels per video pixel";
  }
  if (supersampling < 1 || supersampling > 64) {
    return "supersampling must be 1..64";
  }
  // Noise in 8-bit codes: beyond the code range it is no longer a picture.
  if (!(noise_sigma_dn >= 0.0 && noise_sigma_dn <= 255.0) ||
      !(shot_noise_dn >= 0.0 && shot_noise_dn <= 255.0)) {
    return "noise must be 0..255 codes";
  }
  if (!(exposure_s >= 0.0)) return "exposure must be >= 0";
  if (!(lens_blur_px >= 0.0 && lens_blur_px <= 5.0)) {
    return "lens blur must be 0..5 px";
  }
  if (auto problem = sensor.Problem()) return problem;
  if (!(tone_curve >= 0.0 && tone_curve <= 1.0)) {
    return "tone curve strength must be 0..1";
  }
  if (!(local_tone >= 0.0 && local_tone <= 1.0)) {
    return "local tone mapping strength must be 0..1";
  }
  if (!(sharpen_radius_px >= 0.3 && sharpen_radius_px <= 5.0) ||
      !(sharpen_amount >= 0.0 && sharpen_amount <= 3.0)) {
    return "sharpening must have a radius of 0.3..5 px and an amount of 0..3";
  }
  return std::nullopt;
}

namespace {

// Composites one layer over `image` (CV_32FC3) inside `box`: `shader(p, &c)`
// says whether the plane point p = (y, z) [mm] is inside and its colour.
// Pixels whose corners and centre agree are uniform; the others are
// supersampled `ss` x `ss`.
template <typename Shader>
void Composite(const PixelGrid& pixels,
               const Eigen::Matrix3d& plane_from_normalized, cv::Rect box,
               int ss, const Shader& shader, cv::Mat* image) {
  box &= cv::Rect(0, 0, image->cols, image->rows);
  if (box.empty()) return;
  const auto sample = [&](double u, double v, cv::Vec3f* colour) {
    const Eigen::Vector2d n = pixels.At(u, v);
    const Eigen::Vector3d q = plane_from_normalized * n.homogeneous();
    return shader(Eigen::Vector2d(q.x() / q.z(), q.y() / q.z()), colour);
  };
  cv::parallel_for_(
      cv::Range(box.y, box.y + box.height), [&](const cv::Range& rows) {
        for (int v = rows.start; v < rows.end; ++v) {
          auto* row = image->ptr<cv::Vec3f>(v);
          for (int u = box.x; u < box.x + box.width; ++u) {
            cv::Vec3f c[5];
            const bool in[5] = {sample(u - 0.5, v - 0.5, &c[0]),
                                sample(u + 0.5, v - 0.5, &c[1]),
                                sample(u - 0.5, v + 0.5, &c[2]),
                                sample(u + 0.5, v + 0.5, &c[3]),
                                sample(u, v, &c[4])};
            const int count = in[0] + in[1] + in[2] + in[3] + in[4];
            if (count == 0) continue;
            if (count == 5 && c[0] == c[1] && c[0] == c[2] && c[0] == c[3] &&
                c[0] == c[4]) {
              row[u] = c[0];
              continue;
            }
            cv::Vec3f sum(0, 0, 0), colour;
            int covered = 0;
            for (int j = 0; j < ss; ++j) {
              for (int i = 0; i < ss; ++i) {
                if (sample(u - 0.5 + (i + 0.5) / ss, v - 0.5 + (j + 0.5) / ss,
                           &colour)) {
                  sum += colour;
                  ++covered;
                }
              }
            }
            if (covered == 0) continue;
            const float coverage = static_cast<float>(covered) / (ss * ss);
            row[u] = row[u] * (1.0f - coverage) + sum * (1.0f / (ss * ss));
          }
        }
      });
}

}  // namespace

namespace {

// The video camera's intrinsics at `scale` sensor pixels per video pixel
// side: video pixel i spans sensor pixels [scale i, scale (i + 1)), so its
// centre i is at scale (i + 0.5) - 0.5 on the sensor.
CameraIntrinsics SensorIntrinsics(CameraIntrinsics k, int scale) {
  if (scale == 1) return k;
  k.fx_px *= scale;
  k.fy_px *= scale;
  k.cx_px = scale * (k.cx_px + 0.5) - 0.5;
  k.cy_px = scale * (k.cy_px + 0.5) - 0.5;
  k.width_px *= scale;
  k.height_px *= scale;
  return k;
}

}  // namespace

SceneRenderer::SceneRenderer(const TestPlan& plan, const RenderOptions& options)
    : plan_(plan),
      options_(options),
      camera_(CameraIntrinsics{}, Eigen::Matrix3d::Identity(),
              Eigen::Vector3d::Zero()),
      sensor_camera_(camera_),
      dot_height_(plan.calibration.plane_offset_mm) {
  const Mechanism& m = plan_.mechanism;
  for (const Head& head : m.heads) centre_mm_ += head.rest_mm / m.NumHeads();
  camera_ = Camera::LookingDown(
      options_.intrinsics,
      Eigen::Vector3d(centre_mm_.x(), centre_mm_.y(), dot_height_),
      options_.distance_mm, DegToRad(options_.tilt_x_deg),
      DegToRad(options_.tilt_y_deg));
  sensor_camera_ = Camera::LookingDown(
      SensorIntrinsics(options_.intrinsics, options_.sensor_scale),
      Eigen::Vector3d(centre_mm_.x(), centre_mm_.y(), dot_height_),
      options_.distance_mm, DegToRad(options_.tilt_x_deg),
      DegToRad(options_.tilt_y_deg));

  double reach = 0.0;
  for (const FixedAnchor& a : m.fixed_anchors) {
    reach = std::max(reach, (a.position_mm - centre_mm_).norm());
  }
  ring_inner_mm_ = reach + 6.0;
  ring_outer_mm_ = ring_inner_mm_ + 6.0;
  if (plan_.calibration.tag) {
    const TagSpec& tag = *plan_.calibration.tag;
    const double half_diagonal = tag.size_mm * 10.0 / 8.0 / std::sqrt(2.0);
    tag_center_mm_ = tag.center_mm.value_or(
        centre_mm_ + (ring_outer_mm_ + 6.0 + half_diagonal) *
                         Eigen::Vector2d(1.0, -1.0).normalized());
  }

  auto pixels = std::make_shared<PixelGrid>();
  const CameraIntrinsics& k = sensor_camera_.intrinsics();
  pixels->fx = k.fx_px, pixels->fy = k.fy_px, pixels->cx = k.cx_px,
  pixels->cy = k.cy_px, pixels->width = k.width_px;
  if (sensor_camera_.HasDistortion()) {
    std::vector<cv::Point2d> corners;
    corners.reserve(static_cast<size_t>(k.width_px + 1) * (k.height_px + 1));
    for (int j = 0; j <= k.height_px; ++j) {
      for (int i = 0; i <= k.width_px; ++i)
        corners.emplace_back(i - 0.5, j - 0.5);
    }
    pixels->corners = sensor_camera_.UndistortPixels(corners);
  }
  pixels_ = pixels;
  DrawStatic();
}

namespace {

// The image box of a circle on the plane at `height`.
cv::Rect CircleBox(const Camera& camera, const Eigen::Vector2d& centre,
                   double radius, double height) {
  std::vector<Eigen::Vector2d> circle;
  for (int i = 0; i < 16; ++i) {
    const double a = 2 * std::numbers::pi * i / 16;
    circle.emplace_back(centre +
                        radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return ImageBox(camera, circle, height);
}

}  // namespace

void SceneRenderer::DrawStatic() {
  DrawTable();
  if (options_.ring) DrawRing();
  background_without_tag_ = background_.clone();
  if (plan_.calibration.tag) DrawTag();
  MakeGain();
}

void SceneRenderer::DrawTable() {
  const CameraIntrinsics& k = sensor_camera_.intrinsics();
  const double s = options_.sensor_scale;  // the grain's size in the video
  // Table: a grey-brown surface with coarse and fine grain (seeded).
  cv::RNG rng(options_.seed ^ 0x5EEDF00DULL);
  cv::Mat coarse(k.height_px, k.width_px, CV_32FC1),
      fine(coarse.size(), CV_32FC1);
  rng.fill(coarse, cv::RNG::NORMAL, 0.0, 1.0);
  rng.fill(fine, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(coarse, coarse, cv::Size(), 9.0 * s);
  cv::GaussianBlur(fine, fine, cv::Size(), 1.2 * s);
  cv::Mat grain = coarse * (12.0 / 0.045) + fine * 3.0;
  std::vector<cv::Mat> channels(3);
  for (int c = 0; c < 3; ++c) channels[c] = grain + kTableCode[c];
  cv::merge(channels, background_);
  background_.forEach<cv::Vec3f>(
      [](cv::Vec3f& pixel, const int*) { pixel = LinearLevels(pixel); });
}

// The ring with a pad from each fixed anchor out to it (the mating
// surfaces).
void SceneRenderer::DrawRing() {
  const Mechanism& m = plan_.mechanism;
  const Eigen::Matrix3d on_ring = camera_.NormalizedFromPlane(0.0).inverse();
  Composite(
      *pixels_, on_ring,
      CircleBox(sensor_camera_, centre_mm_, ring_outer_mm_ + 1, 0.0),
      options_.supersampling,
      [&](const Eigen::Vector2d& p, cv::Vec3f* colour) {
        const double r = (p - centre_mm_).norm();
        bool in = r >= ring_inner_mm_ && r <= ring_outer_mm_;
        for (const FixedAnchor& a : m.fixed_anchors) {
          const Eigen::Vector2d out =
              centre_mm_ +
              (a.position_mm - centre_mm_).normalized() * ring_inner_mm_;
          in = in || DistanceToSegment(p, a.position_mm, out) <= 12.5;
        }
        *colour = kRingColor;
        return in;
      },
      &background_);
}

// The tag from libapriltag's own bitmap: total_width cells including the
// white quiet zone; size_mm spans the black border (width_at_border).
void SceneRenderer::DrawTag() {
  const Eigen::Matrix3d on_ring = camera_.NormalizedFromPlane(0.0).inverse();
  const TagBitmap bitmap = Tag36h11Bitmap(plan_.calibration.tag->id);
  const double cell = plan_.calibration.tag->size_mm / bitmap.width_at_border;
  const int cells = bitmap.total_width;
  const double half = cell * cells / 2.0;
  Composite(
      *pixels_, on_ring,
      CircleBox(sensor_camera_, tag_center_mm_, half * std::sqrt(2.0), 0.0),
      options_.supersampling,
      [&](const Eigen::Vector2d& p, cv::Vec3f* colour) {
        const Eigen::Vector2d d = p - tag_center_mm_;
        const double col = std::floor((d.x() + half) / cell);
        const double row = std::floor((half - d.y()) / cell);
        if (col < 0 || row < 0 || col >= cells || row >= cells) return false;
        *colour = bitmap.IsWhite(static_cast<int>(row), static_cast<int>(col))
                      ? kPaperColor
                      : kInkColor;
        return true;
      },
      &background_);
}

void SceneRenderer::MakeGain() {
  const CameraIntrinsics& k = sensor_camera_.intrinsics();
  // Lighting: a linear gradient times cos^4-like vignetting.
  gain_.create(k.height_px, k.width_px, CV_32FC1);
  const double half_diagonal = std::hypot(k.width_px, k.height_px) / 2.0;
  for (int v = 0; v < k.height_px; ++v) {
    auto* row = gain_.ptr<float>(v);
    for (int u = 0; u < k.width_px; ++u) {
      const double x = (u - k.cx_px) / half_diagonal;
      const double y = (v - k.cy_px) / half_diagonal;
      const double gradient =
          1.0 + options_.lighting_gradient * 0.5 * (x - 0.5 * y);
      row[u] = static_cast<float>(
          gradient * (1.0 - options_.vignetting * (x * x + y * y)));
    }
  }
}

Eigen::Vector2d SceneRenderer::Project(const Eigen::Vector3d& point_in_world,
                                       const CameraMotion& motion) const {
  const Eigen::Vector3d p =
      camera_.camera_from_world() * point_in_world + camera_.translation();
  const Eigen::Vector3d n = motion.CurrentFromReference() * (p / p.z());
  return camera_.Distort(n.head<2>() / n.z());
}

SceneRenderer::Plate SceneRenderer::PlateAt(const Eigen::VectorXd& state,
                                            int head) const {
  Plate plate{HeadAt(state, head), 0.0, Eigen::Vector2d::Zero()};
  const int n = plan_.mechanism.NumHeads();
  if (state.size() == 5 * n) {
    plate.lift_mm = state[2 * n + 3 * head];
    plate.tilt_rad = state.segment<2>(2 * n + 3 * head + 1);
  }
  return plate;
}

// The plate turned by the rotation vector (tilt y, tilt z, 0) about its
// centre, raised by its lift: the world point of the plate's point drawn
// at plane position q when flat.
Eigen::Vector3d SceneRenderer::PlatePoint(const Plate& plate,
                                          const Eigen::Vector2d& q) const {
  const Eigen::Vector2d d = q - plate.centre_mm;
  return Eigen::Vector3d(plate.centre_mm.x(), plate.centre_mm.y(),
                         dot_height_ + plate.lift_mm) +
         PlateRotation(plate) * Eigen::Vector3d(d.x(), d.y(), 0.0);
}

Eigen::Matrix3d SceneRenderer::PlateRotation(const Plate& plate) {
  const double angle = plate.tilt_rad.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(
             angle, Eigen::Vector3d(plate.tilt_rad.x(), plate.tilt_rad.y(), 0)
                        .normalized())
      .toRotationMatrix();
}

// The plate's homography: x_c = R_c X + t with X = A (q, 1), A's columns
// the plate's axes and its origin in the world.
Eigen::Matrix3d SceneRenderer::PlateFromNormalized(const Plate& plate) const {
  const Eigen::Matrix3d turn = PlateRotation(plate);
  Eigen::Matrix3d normalized_from_plate;
  normalized_from_plate.col(0) = camera_.camera_from_world() * turn.col(0);
  normalized_from_plate.col(1) = camera_.camera_from_world() * turn.col(1);
  normalized_from_plate.col(2) =
      camera_.camera_from_world() *
          (PlatePoint(plate, Eigen::Vector2d::Zero())) +
      camera_.translation();
  return normalized_from_plate.inverse();
}

std::vector<DotTruth> SceneRenderer::Dots(const Eigen::VectorXd& state,
                                          const CameraMotion& motion) const {
  std::vector<DotTruth> dots;
  for (const MarkerSpec& marker : plan_.markers) {
    const Plate plate = PlateAt(state, marker.head);
    for (const Eigen::Vector2d& offset : marker.layout_mm) {
      const Eigen::Vector3d p = PlatePoint(plate, plate.centre_mm + offset);
      dots.push_back({marker.head, p.head<2>(), Project(p, motion)});
    }
  }
  return dots;
}

std::vector<Eigen::Vector2d> SceneRenderer::HeadPixels(
    const Eigen::VectorXd& state, const CameraMotion& motion) const {
  std::vector<Eigen::Vector2d> pixels;
  for (const MarkerSpec& marker : plan_.markers) {
    const Plate plate = PlateAt(state, marker.head);
    Eigen::Vector2d centre = plate.centre_mm;
    for (const Eigen::Vector2d& offset : marker.layout_mm) {
      centre += offset / static_cast<double>(marker.layout_mm.size());
    }
    pixels.push_back(Project(PlatePoint(plate, centre), motion));
  }
  return pixels;
}

std::vector<Eigen::Vector2d> SceneRenderer::TagCorners(
    const CameraMotion& motion) const {
  if (!plan_.calibration.tag) return {};
  const double h = plan_.calibration.tag->size_mm / 2.0;
  std::vector<Eigen::Vector2d> corners;
  for (const Eigen::Vector2d& c :
       {Eigen::Vector2d(-h, -h), Eigen::Vector2d(h, -h), Eigen::Vector2d(h, h),
        Eigen::Vector2d(-h, h)}) {
    const Eigen::Vector2d p = tag_center_mm_ + c;
    corners.push_back(Project(Eigen::Vector3d(p.x(), p.y(), 0.0), motion));
  }
  return corners;
}

Eigen::Vector2d SceneRenderer::HeadAt(const Eigen::VectorXd& displacements_mm,
                                      int head) const {
  return plan_.mechanism.heads[head].rest_mm +
         displacements_mm.segment<2>(2 * head);
}

void SceneRenderer::DrawMoving(const Eigen::VectorXd& displacements_mm,
                               cv::Mat* image) const {
  DrawBellows(displacements_mm, image);
  for (const MarkerSpec& marker : plan_.markers) {
    DrawHead(marker, PlateAt(displacements_mm, marker.head), image);
  }
  if (options_.red_tube) DrawTube(image);
}

// Bellows, cosmetic: a 22 mm wide band from anchor to head, mid-height.
void SceneRenderer::DrawBellows(const Eigen::VectorXd& displacements_mm,
                                cv::Mat* image) const {
  const Mechanism& m = plan_.mechanism;
  const double height = dot_height_ / 2.0;
  const Eigen::Matrix3d on_bellows =
      camera_.NormalizedFromPlane(height).inverse();
  for (const Actuator& a : m.actuators) {
    const Eigen::Vector2d from = a.anchor.kind == AnchorRef::Kind::kHead
                                     ? HeadAt(displacements_mm, a.anchor.index)
                                     : m.AnchorRestPosition(a);
    const Eigen::Vector2d to = HeadAt(displacements_mm, a.head);
    const Eigen::Vector2d side =
        Eigen::Vector2d(-(to - from).y(), (to - from).x()).normalized() * 11.0;
    Composite(
        *pixels_, on_bellows,
        ImageBox(sensor_camera_,
                 {from + side, from - side, to + side, to - side}, height),
        options_.supersampling,
        [&](const Eigen::Vector2d& p, cv::Vec3f* colour) {
          *colour = kBellowsColor;
          return DistanceToSegment(p, from, to) <= 11.0;
        },
        image);
  }
}

// A disc of `radius` [mm] at `centre` on a head's top face `plate`, drawn
// within the square of half side `box_half_mm` around it.
void SceneRenderer::DrawDisc(const Plate& plate, const Eigen::Vector2d& centre,
                             double radius, double box_half_mm,
                             const cv::Vec3f& bgr, cv::Mat* image) const {
  const Eigen::Vector2d corner(box_half_mm, box_half_mm);
  Composite(
      *pixels_, PlateFromNormalized(plate),
      ImageBox(sensor_camera_, {centre + corner, centre - corner},
               dot_height_ + plate.lift_mm),
      options_.supersampling,
      [&](const Eigen::Vector2d& p, cv::Vec3f* colour) {
        *colour = bgr;
        return (p - centre).squaredNorm() <= radius * radius;
      },
      image);
}

// A head: a triangle with an edge facing each of three attachments (thesis
// figs. 4.2, 4.10), else a disc; its dots and glint on its top face.
void SceneRenderer::DrawHead(const MarkerSpec& marker, const Plate& plate,
                             cv::Mat* image) const {
  const Eigen::Vector2d& centre = plate.centre_mm;
  const double side = plan_.scene.head_side_mm;
  const std::vector<Eigen::Vector2d> attachments =
      AttachmentDirections(plan_.mechanism, marker.head);
  std::vector<Eigen::Vector2d> triangle;
  if (attachments.size() == 3) {
    for (const Eigen::Vector2d& d : attachments) {
      triangle.emplace_back(centre - d * side / std::sqrt(3.0));
    }
    const Eigen::Vector2d e1 = triangle[1] - triangle[0],
                          e2 = triangle[2] - triangle[0];
    if (e1.x() * e2.y() - e1.y() * e2.x() < 0)
      std::swap(triangle[1], triangle[2]);
  }
  const double radius = side / std::sqrt(3.0);
  Composite(
      *pixels_, PlateFromNormalized(plate),
      ImageBox(sensor_camera_,
               {centre + Eigen::Vector2d(radius, radius),
                centre - Eigen::Vector2d(radius, radius)},
               dot_height_ + plate.lift_mm),
      options_.supersampling,
      [&](const Eigen::Vector2d& p, cv::Vec3f* colour) {
        *colour = kHeadColor;
        return triangle.empty() ? (p - centre).norm() <= side / 2.0
                                : InPolygon(triangle, p);
      },
      image);
  const cv::Vec3f dot_color = MarkerColorBgr(marker.color);
  for (const Eigen::Vector2d& offset : marker.layout_mm) {
    const double r = marker.dot_diameter_mm / 2.0;
    DrawDisc(plate, centre + offset, r, r, dot_color, image);
  }
  if (options_.glint) {
    DrawDisc(plate, centre + Eigen::Vector2d(0.8, -0.6), 1.3, 2.0, kGlintColor,
             image);
  }
}

// A 5 mm red air tube across the lower left of the frame, above the scene.
void SceneRenderer::DrawTube(cv::Mat* image) const {
  const double height = dot_height_ + 10.0;
  const Eigen::Matrix3d on_tube = camera_.NormalizedFromPlane(height).inverse();
  const std::vector<Eigen::Vector2d> path = {
      centre_mm_ + Eigen::Vector2d(-200, -15),
      centre_mm_ + Eigen::Vector2d(-120, -45),
      centre_mm_ + Eigen::Vector2d(-85, -75),
      centre_mm_ + Eigen::Vector2d(-70, -140)};
  const cv::Vec3f red = MarkerColorBgr("red");
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector2d& a = path[i];
    const Eigen::Vector2d& b = path[i + 1];
    Composite(
        *pixels_, on_tube,
        ImageBox(sensor_camera_,
                 {a + Eigen::Vector2d(3, 3), a - Eigen::Vector2d(3, 3),
                  b + Eigen::Vector2d(3, 3), b - Eigen::Vector2d(3, 3)},
                 height),
        options_.supersampling,
        [&](const Eigen::Vector2d& p, cv::Vec3f* colour) {
          *colour = red;
          return DistanceToSegment(p, a, b) <= 2.5;
        },
        image);
  }
}

}  // namespace softbench
