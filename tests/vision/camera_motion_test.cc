// The camera-motion model and the static patches that measure it.
#include "vision/camera_motion.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "vision/camera_path.h"
#include "vision/color_transfer.h"
#include "vision/plane_mapping.h"
#include "vision/static_patches.h"

namespace softbench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

CameraIntrinsics Phone() {
  CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1920, 1080);
  k.distortion = {-0.08, 0.01, 0.0, 0.0, 0.0};
  return k;
}

TEST(CameraMotion, FromImageShiftShiftsThePrincipalPointAsAsked) {
  const CameraIntrinsics k = Phone();
  for (const Eigen::Vector2d& shift :
       {Eigen::Vector2d(0.37, -0.21), Eigen::Vector2d(2.0, 0.5),
        Eigen::Vector2d(-6.0, 3.0)}) {
    const CameraMotion m = CameraMotion::FromImageShift(k, shift, 0.0);
    // Pan and tilt compose as one axis-angle: exact to second order.
    EXPECT_LT((m.ShiftPx(k) - shift).norm(), 1e-5) << shift.transpose();
    // A roll turns the image about the principal point, leaving it put
    // but for the small angles' coupling (about roll x shift / 2).
    const double roll = 0.05 * kDeg;
    const CameraMotion rolled = CameraMotion::FromImageShift(k, shift, roll);
    EXPECT_LT((rolled.ShiftPx(k) - shift).norm(), roll * shift.norm());
    EXPECT_DOUBLE_EQ(rolled.roll_rad(), 0.05 * kDeg);
  }
}

TEST(CameraMotion, IsARotationTimesAnImageScale) {
  CameraMotion m;
  m.rotation_rad = {1e-3, -2e-3, 5e-4};
  m.scale = 1.002;
  const Eigen::Matrix3d h = m.CurrentFromReference();
  const Eigen::Matrix3d r =
      Eigen::Vector3d(1 / m.scale, 1 / m.scale, 1).asDiagonal() * h;
  EXPECT_LT((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  EXPECT_TRUE(CameraMotion().CurrentFromReference().isIdentity(0.0));
}

// What the moved camera sees at a pixel, the reference mapping said of the
// pixel the still camera saw it at: AfterCameraMotion keeps the plane.
TEST(PlaneMapping, AfterCameraMotionMapsAMovedPixelToTheSamePoint) {
  const CameraIntrinsics k = Phone();
  const Camera camera =
      Camera::LookingDown(k, {40, 30, 16}, 490, 4 * kDeg, -2 * kDeg);
  const double h = 12.5;
  const std::array<Eigen::Vector2d, 4> corners = {
      camera.Project({-h, -h, 0}), camera.Project({h, -h, 0}),
      camera.Project({h, h, 0}), camera.Project({-h, h, 0})};
  const PlaneMapping reference = PlaneMapping::FromTag(k, corners, 25, 16);
  const CameraMotion motion = CameraMotion::FromImageShift(
      k, Eigen::Vector2d(1.7, -2.3), 0.08 * kDeg, 1.001);
  const PlaneMapping moved =
      reference.AfterCameraMotion(motion.CurrentFromReference());
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(40, 30), Eigen::Vector2d(70, 5)}) {
    const Eigen::Vector2d still = camera.Project({p.x(), p.y(), 16});
    const Eigen::Vector3d n =
        motion.CurrentFromReference() * camera.Undistort(still).homogeneous();
    const Eigen::Vector2d now = camera.Distort(n.head<2>() / n.z());
    EXPECT_GT((now - still).norm(), 1.0);
    EXPECT_LT((moved.ToPlane(now) - p).norm(), 1e-6) << p.transpose();
    EXPECT_LT((moved.ToPixel(p) - now).norm(), 1e-6);
  }
}

// Ten seconds of a camera at 30 fps that drifts (0.05 px/s) and is knocked
// once at 5 s (2, -1 px and 0.05° of roll), trembling by `tremor_px` RMS
// from frame to frame; measured with `noise_px` of registration noise.
struct KnockedCamera {
  std::vector<double> times;
  std::vector<CameraMotion> truth, measured;
};
KnockedCamera Knocked(const CameraIntrinsics& k, double tremor_px,
                      double noise_px, int seed) {
  KnockedCamera c;
  cv::RNG rng(seed);
  for (int i = 0; i < 300; ++i) {
    const double t = i / 30.0;
    const Eigen::Vector2d shift =
        Eigen::Vector2d(0.05 * t + (t >= 5.0 ? 2.0 : 0.0),
                        t >= 5.0 ? -1.0 : 0.0) +
        Eigen::Vector2d(rng.gaussian(tremor_px), rng.gaussian(tremor_px));
    const double roll = t >= 5.0 ? 0.05 * kDeg : 0.0;
    c.times.push_back(t);
    c.truth.push_back(CameraMotion::FromImageShift(k, shift, roll));
    c.measured.push_back(CameraMotion::FromImageShift(
        k,
        shift + Eigen::Vector2d(rng.gaussian(noise_px), rng.gaussian(noise_px)),
        roll + rng.gaussian(1e-5)));
  }
  return c;
}

// A still camera's registration noise (a codec's wobble of still edges,
// 0.004 px): the path keeps the knock as a step and the drift's slope right
// up to it, and averages the noise away.
TEST(CameraPath, KeepsAKnockAndADriftAndAveragesNoise) {
  const CameraIntrinsics k = Phone();
  const auto [times, truth, measured] = Knocked(k, 0.0, 0.004, 5);
  const std::vector<bool> valid(times.size(), true);
  const std::vector<CameraMotion> path =
      SmoothCameraPath(k, times, measured, valid, 0.05);
  double worst = 0.0, raw_rms = 0.0, rms = 0.0;
  for (size_t i = 0; i < times.size(); ++i) {
    const double error = (path[i].ShiftPx(k) - truth[i].ShiftPx(k)).norm();
    worst = std::max(worst, error);
    rms += error * error / times.size();
    raw_rms += (measured[i].ShiftPx(k) - truth[i].ShiftPx(k)).squaredNorm() /
               times.size();
  }
  // The frames at the knock keep their own (noisy) motion: 4 sigma.
  EXPECT_LT(worst, 0.023);
  EXPECT_LT(std::sqrt(rms), 0.4 * std::sqrt(raw_rms));
  // Frames far from the knock are within a thousandth.
  EXPECT_LT((path[60].ShiftPx(k) - truth[60].ShiftPx(k)).norm(), 0.001);
  EXPECT_LT((path[200].ShiftPx(k) - truth[200].ShiftPx(k)).norm(), 0.001);
  EXPECT_NEAR(path[200].roll_rad(), 0.05 * kDeg, 5e-6);
}

// A camera that trembles (0.06 px RMS from frame to frame, as on a phone's
// tripod): its tremor is real motion of the image, so every frame keeps its
// own registration (measured to 0.004 px).
TEST(CameraPath, FollowsTremorFrameByFrame) {
  const CameraIntrinsics k = Phone();
  const auto [times, truth, measured] = Knocked(k, 0.06, 0.004, 6);
  const std::vector<CameraMotion> path = SmoothCameraPath(
      k, times, measured, std::vector<bool>(times.size(), true), 0.05);
  double rms = 0.0;
  for (size_t i = 0; i < times.size(); ++i) {
    rms +=
        (path[i].ShiftPx(k) - truth[i].ShiftPx(k)).squaredNorm() / times.size();
  }
  // Two axes of 0.004 px; smoothed, the path would miss the tremor's 0.085.
  EXPECT_LT(std::sqrt(rms), 0.008);
}

TEST(CameraPath, LeavesUnregisteredFramesAndStretchesApart) {
  const CameraIntrinsics k = Phone();
  const std::vector<double> times = {0.0, 0.033, 0.067, 5.0, 5.033};
  std::vector<CameraMotion> raw;
  for (double x : {0.0, 0.0, 9.0, 1.0, 1.0}) {
    raw.push_back(CameraMotion::FromImageShift(k, {x, 0.0}, 0.0));
  }
  const std::vector<CameraMotion> path =
      SmoothCameraPath(k, times, raw, {true, true, false, true, true}, 0.05);
  EXPECT_NEAR(path[0].ShiftPx(k).x(), 0.0, 1e-9);
  EXPECT_NEAR(path[2].ShiftPx(k).x(), 9.0, 1e-9);  // as given
  EXPECT_NEAR(path[3].ShiftPx(k).x(), 1.0, 1e-9);  // its own stretch
}

// A smooth image of light (sums of Gaussian spots and a soft straight edge)
// whose shifted copy is exact, the function itself evaluated at x - shift,
// encoded with the BT.709 curve as a camera does (full range, 8 bits).
cv::Mat Scene(const Eigen::Vector2d& shift) {
  cv::Mat image(240, 320, CV_8UC1);
  cv::RNG rng(7);
  std::vector<std::array<double, 4>> spots;  // x, y, sigma, amplitude
  for (int i = 0; i < 240; ++i) {
    spots.push_back({rng.uniform(0.0, 160.0), rng.uniform(0.0, 240.0),
                     rng.uniform(2.0, 4.0), rng.uniform(-70.0, 70.0)});
  }
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      const double x = u - shift.x(), y = v - shift.y();
      double value = 128.0;
      for (const auto& s : spots) {
        const double d2 = (x - s[0]) * (x - s[0]) + (y - s[1]) * (y - s[1]);
        value += s[3] * std::exp(-d2 / (2 * s[2] * s[2]));
      }
      if (x > 160.0) {
        // Right half: a soft edge along (2, 1), dark below-left.
        const double across =
            ((x - 240.0) * 1.0 - (y - 120.0) * 2.0) / std::sqrt(5.0);
        value = 60.0 + 140.0 / (1.0 + std::exp(-across / 1.2));
      }
      image.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(
          255.0 *
          FromLinear(Transfer::kSdr, std::clamp(value, 0.0, 255.0) / 255.0));
    }
  }
  return image;
}

// The patches are followed in light (StaticPatchOptions::luma_encoding):
// read through the wrong curve (PQ's), the same patches are off by more.
TEST(StaticPatches, FollowSpotsBothWaysAndAnEdgeAcrossItself) {
  const cv::Mat reference = Scene(Eigen::Vector2d::Zero());
  // Not across the seam between the spots and the edge: a step there is
  // no band-limited image, and its shifted samples are not a shift.
  cv::Mat allowed(reference.size(), CV_8UC1, cv::Scalar(255));
  allowed.colRange(140, 185).setTo(0);
  const Eigen::Vector2d shift(0.73, -0.41);  // a frame-to-frame step
  const cv::Mat moved_scene = Scene(shift);
  // The largest error of a patch (across the edge only for an edge patch).
  const auto worst_error = [&](const LumaEncoding& encoding) {
    StaticPatchOptions options;
    options.luma_encoding = encoding;
    const StaticPatches patches(reference, allowed, options);
    EXPECT_GE(patches.size(), 3);
    int corners = 0, edges = 0;
    double worst = 0.0;
    for (const PatchMatch& m :
         patches.Track(moved_scene, patches.reference_px())) {
      EXPECT_TRUE(m.found) << m.reference_px.transpose();
      const Eigen::Vector2d moved = m.pixel - m.reference_px;
      if (m.normal == Eigen::Vector2d::Zero()) {
        ++corners;
        worst = std::max(worst, (moved - shift).norm());
      } else {
        ++edges;
        // Only the motion across the edge is measured.
        worst = std::max(worst, std::abs(m.normal.dot(moved - shift)));
        EXPECT_NEAR(m.normal.dot(Eigen::Vector2d(2, 1).normalized()), 0.0,
                    0.05);
      }
    }
    EXPECT_GT(corners, 0);
    EXPECT_GT(edges, 0);
    return worst;
  };
  const double in_light = worst_error({Transfer::kSdr, true});
  const double wrong_curve = worst_error({Transfer::kPq, true});
  EXPECT_LT(in_light, 0.02);
  EXPECT_GT(wrong_curve, 2 * in_light);
}

TEST(StaticPatches, TakeNoneFromWeakTextureOrOutsideTheMask) {
  cv::Mat grain(240, 320, CV_8UC1);
  cv::RNG(3).fill(grain, cv::RNG::NORMAL, 120, 2);  // a codec's victim
  EXPECT_EQ(StaticPatches(grain, cv::Mat()).size(), 0);
  const cv::Mat scene = Scene(Eigen::Vector2d::Zero());
  EXPECT_EQ(StaticPatches(scene, cv::Mat::zeros(scene.size(), CV_8UC1)).size(),
            0);
}

// The structure tensor is summed band by band of cells, not over the whole
// frame at once; every sum is exact, so each patch is still its cell's
// strongest point by the whole frame's sums, near the bands' edges too (a
// band that read its neighbours' rows as a border would not be).
TEST(StaticPatches, TakeEachCellsStrongestPointOfTheWholeFrame) {
  for (const int depth : {CV_8U, CV_16U}) {
    cv::Mat texture(480, 640, CV_32F);
    cv::RNG(11).fill(texture, cv::RNG::NORMAL, 0.5, 1.0);
    cv::GaussianBlur(texture, texture, {0, 0}, 1.2);
    cv::Mat luma;
    texture.convertTo(luma, depth, depth == CV_8U ? 255.0 : 65535.0);
    StaticPatchOptions options;
    options.max_patches = 1000;
    const StaticPatches patches(luma, cv::Mat(), options);
    // The whole frame's sums, in 8-bit levels.
    cv::Mat image, gx, gy, xx, yy;
    luma.convertTo(image, CV_32F, depth == CV_16U ? 1.0 / 256.0 : 1.0);
    cv::Sobel(image, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
    cv::Sobel(image, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
    const int h = options.half_size_px, side = 2 * h + 1, border = 2 * h + 8;
    const int cell = static_cast<int>(options.cell_px);
    cv::boxFilter(gx.mul(gx), xx, CV_32F, {side, side}, {-1, -1}, false);
    cv::boxFilter(gy.mul(gy), yy, CV_32F, {side, side}, {-1, -1}, false);
    const cv::Mat strength = xx + yy;
    ASSERT_GT(patches.size(), 40);
    int near_band_edge = 0;
    for (const Eigen::Vector2d& centre : patches.reference_px()) {
      const int u = static_cast<int>(centre.x()),
                v = static_cast<int>(centre.y());
      const int x0 = border + (u - border) / cell * cell;
      const int y0 = border + (v - border) / cell * cell;
      double strongest = 0.0;
      cv::Point at;
      cv::minMaxLoc(strength(cv::Rect(x0, y0, cell, cell)), nullptr, &strongest,
                    nullptr, &at);
      EXPECT_EQ(cv::Point(u - x0, v - y0), at)
          << depth << " " << centre.transpose();
      near_band_edge += (v - y0 < h || y0 + cell - 1 - v < h);
    }
    EXPECT_GT(near_band_edge, 5);
  }
}

TEST(StaticPatches, LoseAPatchThatIsCovered) {
  const cv::Mat reference = Scene(Eigen::Vector2d::Zero());
  const StaticPatches patches(reference, cv::Mat());
  cv::Mat covered = reference.clone();
  covered.colRange(0, 160).setTo(200);  // a hand over the spots
  int found = 0;
  for (const PatchMatch& m : patches.Track(covered, patches.reference_px())) {
    if (m.reference_px.x() < 150) {
      EXPECT_FALSE(m.found);
    }
    found += m.found;
  }
  EXPECT_GT(found, 0);  // the edge is still there
}

}  // namespace
}  // namespace softbench
