#ifndef SOFTBENCH_PIPELINES_SYNTHETIC_SCENE_RENDERER_H_
#define SOFTBENCH_PIPELINES_SYNTHETIC_SCENE_RENDERER_H_

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/synthetic/bayer_sensor.h"
#include "pipelines/synthetic/bench_conditions.h"
#include "vision/camera.h"
#include "vision/camera_motion.h"

namespace softbench {

struct RenderOptions {
  // Default: the thesis's iPhone 12 Pro at 1080p, 52 mm equivalent (fig. 4.7).
  CameraIntrinsics intrinsics =
      CameraIntrinsics::FromEquivalentFocalLength(52.0, 1920, 1080);
  double distance_mm = 475.0;  // camera to the head tops (fig. 4.7)
  double tilt_x_deg = 0.0;     // about the image x axis
  double tilt_y_deg = 0.0;     // about the image y axis
  int supersampling = 16;      // subsamples per pixel side on edges
  // Temporal noise after a phone's denoising: Gaussian read noise [8-bit
  // levels] and signal-dependent variance per level.
  double noise_sigma_dn = 0.6;
  double shot_noise_dn = 0.01;
  // The lens's blur, in light before the sensor: a Gaussian of this sigma
  // [px]; 0 is none (each pixel the exact average of its area's light).
  double lens_blur_px = 0.0;
  // The sensor's colour filter, raw noise and demosaicing, on the exposed
  // light before the camera's curve (issue 28); none by default.
  BayerSensorOptions sensor;
  // Sensor pixels per video pixel side (1..4): a phone reads more pixels
  // than its video has (12 MP for 1080p or 4K) and scales the demosaiced
  // light down by area; the scene is drawn, moved, blurred and filtered at
  // the sensor's size. 1: the sensor is the video's size.
  int sensor_scale = 1;
  // A phone's processing on its codes after the curve, which the video's
  // metadata does not describe (issue 28). tone_curve: strength k in
  // [0, 1] of an S-curve, (1 - k) c + k (3 c^2 - 2 c^3) on codes c in
  // [0, 1] (darker shadows, brighter highlights); 0 is none.
  double tone_curve = 0.0;
  // Local tone mapping (issue 28): a smooth gain on the light before the
  // curve, from the frame's own luma on a coarse grid (cells of 1/32 of the
  // frame's height, blurred over 1.5 cells and interpolated), as phones
  // brighten shadows and dim highlights region by region. Strength s in
  // [0, 1]: gain (luma_local / 0.18)^-s, within 1/4..4; 0 is none.
  double local_tone = 0.0;
  // Unsharp-mask sharpening on the codes: c + amount (c - blur(c)) with a
  // Gaussian of sigma sharpen_radius_px; amount 0 is none.
  double sharpen_radius_px = 1.0;
  double sharpen_amount = 0.0;
  double lighting_gradient = 0.12;  // relative brightness change across
  double vignetting = 0.2;          // relative darkening at the corners
  bool red_tube = false;            // a red air tube crossing the frame
  bool glint = false;               // a specular glint on each head
  // The ring and its pads: static structure beside the tag that the
  // registration can use (false: a plain table around the mechanism).
  bool ring = true;
  double exposure_s = 1.0 / 60.0;
  bool motion_blur = true;
  uint64_t seed = 1;
  // Frames as CV_16UC3 (65535 = white) instead of CV_8UC3, for 10 and
  // 12-bit video: the sensor's levels are kept between 8-bit steps.
  bool sixteen_bit = false;

  std::optional<std::string> Problem() const;
};

// Pixel to normalised image coordinates, with distortion (scene_renderer.cc).
struct PixelGrid;

// The truth of one dot in a frame.
struct DotTruth {
  int head = 0;
  Eigen::Vector2d plane_mm;  // world (y, z) of its centre on the dot plane
  Eigen::Vector2d pixel;     // projected centre (distortion applied)
};

// Draws the bench scene of a test plan (thesis 4.1.3, fig. 4.7): textured
// table, ring, actuators, heads with coloured dots and the AprilTag, seen by
// the camera of RenderOptions. Dot, head and tag edges are anti-aliased from
// the true projected geometry: each pixel's coverage is the fraction of its
// area whose back-projection onto the shape's plane falls inside the shape
// (supersampled on edges), so a perfect measurement recovers the geometry.
class SceneRenderer {
 public:
  SceneRenderer(const TestPlan& plan, const RenderOptions& options);

  const Camera& camera() const { return camera_; }

  // The frame in linear light at the sensor's size (float BGR, 8-bit
  // levels, before lighting, the camera's transfer curve and noise) with the
  // heads at each of `displacement_samples` (y1, z1, ...), averaged: several
  // samples across the exposure give motion blur.
  cv::Mat RenderLinear(const std::vector<Eigen::VectorXd>& displacement_samples,
                       bool tag_visible = true) const;
  // The 8-bit frame as the camera records it: RenderLinear seen by the
  // camera after `conditions.motion` (the linear frame resampled exactly
  // along the moved camera's rays, bilinearly in full precision; line by
  // line after its own motion under a rolling shutter), then the
  // lens's blur, exposure, white balance, lighting, vignetting, the Bayer
  // sensor (RenderOptions::sensor), the scaling from the sensor's size to
  // the video's, the BT.709 curve, the phone's tone curve and sharpening,
  // and noise in codes (seeded by the
  // options' seed and `frame_index`). CV_8UC3, or CV_16UC3 with
  // RenderOptions::sixteen_bit.
  cv::Mat Render(const std::vector<Eigen::VectorXd>& displacement_samples,
                 int64_t frame_index,
                 const FrameConditions& conditions = {}) const;

  // The dots of the heads in `state`, seen by the camera after `motion`.
  // A head state is the displacements (y1, z1, ..., yN, zN) [mm], and may
  // go on with each head's lift toward the camera [mm] and tilt about
  // world y and z [rad] (HeadTimeline::StateAt); without them the heads
  // are flat on the dot plane. Render's samples are head states too.
  std::vector<DotTruth> Dots(const Eigen::VectorXd& state,
                             const CameraMotion& motion = {}) const;
  // The centre of each head's dots, projected (distortion applied).
  std::vector<Eigen::Vector2d> HeadPixels(
      const Eigen::VectorXd& state, const CameraMotion& motion = {}) const;
  // The tag's four outer black-border corners in pixels, in AprilTag's order
  // (counter-clockwise in the printed tag, starting bottom-left).
  std::vector<Eigen::Vector2d> TagCorners(
      const CameraMotion& motion = {}) const;
  double dot_plane_height_mm() const { return dot_height_; }

 private:
  // The static layers (background_, background_without_tag_) and gain_.
  void DrawStatic();
  void DrawTable();
  void DrawRing();
  void DrawTag();
  void MakeGain();
  // A world point's pixel in the camera after `motion`.
  Eigen::Vector2d Project(const Eigen::Vector3d& point_in_world,
                          const CameraMotion& motion) const;
  // `linear` as the camera after `conditions`' motion sees it (each line
  // after its own under a rolling shutter).
  cv::Mat Moved(const cv::Mat& linear, const FrameConditions& conditions) const;
  // The moving layers at the heads' displacements, onto `image`.
  void DrawMoving(const Eigen::VectorXd& displacements_mm,
                  cv::Mat* image) const;
  Eigen::Vector2d HeadAt(const Eigen::VectorXd& displacements_mm,
                         int head) const;
  // A head's top face: its centre on the plane when flat [mm], its lift
  // [mm] and its tilt (rotation vector about world y and z) [rad].
  struct Plate {
    Eigen::Vector2d centre_mm;
    double lift_mm = 0.0;
    Eigen::Vector2d tilt_rad;
  };
  Plate PlateAt(const Eigen::VectorXd& state, int head) const;
  static Eigen::Matrix3d PlateRotation(const Plate& plate);
  Eigen::Vector3d PlatePoint(const Plate& plate,
                             const Eigen::Vector2d& q) const;
  // Normalised image coordinates to the plate's (plane positions when
  // flat), for Composite.
  Eigen::Matrix3d PlateFromNormalized(const Plate& plate) const;
  void DrawBellows(const Eigen::VectorXd& displacements_mm,
                   cv::Mat* image) const;
  void DrawHead(const MarkerSpec& marker, const Plate& plate,
                cv::Mat* image) const;
  void DrawDisc(const Plate& plate, const Eigen::Vector2d& centre,
                double radius, double box_half_mm, const cv::Vec3f& bgr,
                cv::Mat* image) const;
  void DrawTube(cv::Mat* image) const;

  TestPlan plan_;
  RenderOptions options_;
  Camera camera_;         // the video's: the truth
  Camera sensor_camera_;  // the same at the sensor's pixels: the drawing
  double dot_height_;
  Eigen::Vector2d tag_center_mm_ = Eigen::Vector2d::Zero();
  double ring_inner_mm_ = 0.0, ring_outer_mm_ = 0.0;
  Eigen::Vector2d centre_mm_ = Eigen::Vector2d::Zero();
  std::shared_ptr<const PixelGrid> pixels_;
  cv::Mat background_;              // CV_32FC3, static layers
  cv::Mat background_without_tag_;  // the same with the tag taken away
  cv::Mat gain_;                    // CV_32FC1, lighting x vignetting
};

// BGR of a marker colour name (test_plan.h's list), as printed dots: linear
// light in 8-bit levels (the ink's BT.709 codes linearised).
cv::Vec3f MarkerColorBgr(const std::string& name);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_SYNTHETIC_SCENE_RENDERER_H_
