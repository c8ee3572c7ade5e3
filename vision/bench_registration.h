#ifndef SOFTBENCH_VISION_BENCH_REGISTRATION_H_
#define SOFTBENCH_VISION_BENCH_REGISTRATION_H_

#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vision/camera.h"
#include "vision/camera_motion.h"
#include "vision/static_patches.h"
#include "vision/tag_detector.h"

namespace softbench {

struct BenchRegistrationOptions {
  // Edge profiles across the tag's border: their half length bounds how far
  // the tag may move between two frames (a bump of a few pixels) and still
  // be followed without a fresh detection.
  TagDetectorOptions tag;
  // Static texture followed beside the tag (table grain, the ring, mounts).
  StaticPatchOptions patches;
  // Re-fits of the tag's edges per frame, each from the corners the last
  // one found (the profiles re-centre on the edge after a jump), until no
  // corner moves more than refit_tolerance_px. The edge's integral is
  // unbiased wherever its profiles start within a fraction of a pixel, so
  // only a knock needs the second fit; tremor (< 0.1 px) does not.
  int max_refits = 2;
  double refit_tolerance_px = 0.25;
  // Largest RMS distance of a tag edge's points from its line [px]: more
  // means something covers or shadows the border.
  double max_edge_rms_px = 0.25;
  // Points (tag corners, patches) further than this from the fitted motion
  // [px] are not static (a tube that moves, a hand) and are left out.
  double outlier_px = 0.3;
  // A frame without the tag needs this many static patches that agree; with
  // fewer, the tag gives the camera's pan and tilt only. The roll is fitted
  // from this many patches, the scale (focus breathing) from
  // min_patches_for_scale: a tag a few per cent of the frame wide turns a
  // video codec's wobble of its edges (a few hundredths of a pixel) into
  // tenths of a pixel of roll at the heads.
  int min_patches = 6;
  int min_patches_for_scale = 12;
  // Largest RMS misfit of the points kept [px]: more, and the frame is left
  // out rather than measured against a doubtful registration.
  double max_residual_px = 0.2;

  std::optional<std::string> Problem() const;
};

// The tag in the reference frame.
struct TagReference {
  int id = 0;
  std::array<Eigen::Vector2d, 4> corners;  // libapriltag's order
};

// One frame registered to the bench (or why not).
struct FrameRegistration {
  bool registered = false;
  std::string why_not;  // when not registered
  CameraMotion motion;  // since the reference frame
  Eigen::Vector2d shift_px = Eigen::Vector2d::Zero();  // motion.ShiftPx
  double residual_px = 0.0;  // RMS misfit of the points kept
  bool tag_used = false;
  // The tag's corners located in this frame, when they were used.
  std::optional<std::array<Eigen::Vector2d, 4>> tag_corners;
  int patches_used = 0;
  // 2: pan and tilt; 3: and roll; 4: and scale.
  int parameters = 2;
};

// Registers every frame to the fixed bench: the camera's motion since the
// reference frame (CameraMotion: a rotation and a scale) is fitted to the
// tag's four corners, re-located in each frame from its edges to a few
// hundredths of a pixel, and to strongly structured static patches spread
// over the frame (StaticPatches: the ring's rim, mounts). The patches give
// the roll a lever of the whole image; the tag alone gives pan and tilt.
// Points that disagree with the rest are dropped, so parts that move do not
// pull the fit; a frame with neither the tag nor enough static patches is
// not registered (and not measured).
class BenchRegistration {
 public:
  // `reference_luma`: the reference frame; `static_mask` (CV_8UC1, non-zero
  // where the scene is static, or empty: anywhere) limits the patches;
  // `tag`: the tag in that frame, if the plan has one.
  BenchRegistration(const CameraIntrinsics& intrinsics,
                    const cv::Mat& reference_luma, const cv::Mat& static_mask,
                    const std::optional<TagReference>& tag,
                    const BenchRegistrationOptions& options = {});

  FrameRegistration Register(const cv::Mat& luma);

  int patch_count() const { return patches_.size(); }

 private:
  struct Point {
    Eigen::Vector3d ray;    // reference, normalised homogeneous
    Eigen::Vector2d pixel;  // observed now
    bool tag_corner = false;
    // An edge patch's normal: only the misfit along it counts.
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  };
  // The misfit of a point to a motion [px] (along an edge's normal), the
  // motion given as its CurrentFromReference(): built once per fit step,
  // not once per point.
  Eigen::Vector2d Misfit(const Eigen::Matrix3d& current_from_reference,
                         const Point& p) const;
  // The tag's corners now, if they can be found.
  std::optional<std::array<Eigen::Vector2d, 4>> FindTag(const cv::Mat& luma);
  // The corners found from `start`, re-fitted until they settle.
  std::optional<std::array<Eigen::Vector2d, 4>> Follow(
      const cv::Mat& luma, std::array<Eigen::Vector2d, 4> start) const;
  // Fits the first `parameters` of `motion` (pan, tilt, roll, scale) to
  // the points with non-zero weight; the RMS misfit.
  double FitMotion(const std::vector<Point>& points,
                   const std::vector<double>& weights, int parameters,
                   CameraMotion* motion) const;
  Eigen::Vector2d Predict(const Eigen::Matrix3d& current_from_reference,
                          const Eigen::Vector3d& ray) const;
  // A robust start without the tag: weight 1 for the points that moved
  // with the median since `motion` (a bump moves them all alike; a moving
  // part does not), 0 for the others.
  std::vector<double> MedianMotionWeights(const std::vector<Point>& points,
                                          const CameraMotion& motion) const;
  // Refits `motion` to every point near it, with the start gate and then the
  // final one, freeing roll and scale when enough patches pin them; fills
  // `out`'s tag_used, patches_used and parameters and returns the RMS
  // misfit.
  double FitWithinGates(const std::vector<Point>& points, bool tag_found,
                        std::vector<double>* weights, CameraMotion* motion,
                        FrameRegistration* out) const;

  Camera camera_;  // intrinsics only: distortion and projection
  BenchRegistrationOptions options_;
  std::optional<TagReference> tag_;
  std::array<Eigen::Vector3d, 4> tag_rays_;
  std::array<Eigen::Vector2d, 4> last_corners_;
  StaticPatches patches_;
  std::vector<Eigen::Vector3d> patch_rays_;
  CameraMotion last_motion_;
  std::unique_ptr<TagDetector> detector_;  // made when first needed
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_BENCH_REGISTRATION_H_
