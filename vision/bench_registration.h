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
#include "vision/rolling_shutter.h"
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
  // A still camera's tag is re-located on every tag_stride-th frame only
  // (1: every frame); on the frames between, its corners are held from the
  // last frame that located them, and every static patch is aligned afresh.
  // Re-fitting the tag's edges is most of registration's cost, and a still
  // camera's tag does not move: the held corners pin the fit as the fresh
  // ones would. A frame whose fit moves the camera further than
  // still_step_px from the last frame's, or whose patches do not pin all
  // four parameters, is registered in full instead (a knock moves the
  // patches away from the held corners).
  int tag_stride = 4;
  // The camera is still while, over the last still_frames registered
  // frames, its shift moves from one frame to the next by a robust scatter
  // under still_tremor_px (1.4826 times the median absolute deviation, over
  // sqrt 2; the larger axis) and never by more than still_step_px. Half the
  // camera path's tremor_px: a camera that trembles keeps every frame's own
  // registration, tag included. A still 1080p camera scatters by under
  // 0.003 px, a phone on a tripod by 0.03-0.08 px.
  int still_frames = 16;
  double still_tremor_px = 0.005;
  double still_step_px = 0.05;

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
  // The tag was not looked for: a still camera between its tag_stride
  // frames, registered with its corners held (tag_stride).
  bool tag_skipped = false;
  // The points' misfits against a rolling shutter's shear
  // (EstimateRollingShutter), when registered.
  ShutterShearSums shear_sums;
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

  // Registers the next frame of the video (frames in time order: a still
  // camera's tag is re-located at a stride, see tag_stride).
  FrameRegistration Register(const cv::Mat& luma);

  int patch_count() const { return patches_.size(); }

  // Forgets the frames registered so far, as after a seek: the next frame
  // is registered as the first after the reference (its tag followed from
  // the reference's corners, the fit started at no motion, no stride). So a
  // span's registration does not depend on which spans were registered
  // before it, or by which copy.
  void Restart();

  // Another registration to the same reference, in this one's state, for a
  // worker of its own: the patches are copied, not chosen again (choosing
  // them is a pass over the whole reference frame, 0.1 s of CPU at 4K).
  std::unique_ptr<BenchRegistration> Clone() const;

 private:
  // Clone's copy: everything but the tag detector, which holds
  // libapriltag's working state and is made again when first needed.
  BenchRegistration(const BenchRegistration& other);

  // The motion's matrix and those a step along each fitted parameter away
  // (Stepped in the .cc): FitMotion's forward differences.
  using SteppedMatrices = std::array<Eigen::Matrix3d, 5>;
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
  // A point's misfit's Jacobian in the first `moved` parameters, from
  // `m` and its `misfit` at m[0] (both scaled by `root`, a weight's root).
  Eigen::Matrix<double, 2, 4> MisfitJacobian(const SteppedMatrices& m,
                                             int moved, const Point& p,
                                             const Eigen::Vector2d& misfit,
                                             double root = 1.0) const;
  // The kept points' misfits against a rolling shutter's shear, at the
  // fitted `motion` (ShutterShearSums); `size` the frame's.
  ShutterShearSums ShearSums(const std::vector<Point>& points,
                             const std::vector<double>& weights, int parameters,
                             const CameraMotion& motion,
                             const cv::Size& size) const;
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
  // Registers `luma` by the tag's `corners` (when found) and the static
  // patches; `tag_looked_for` false: the corners are held from the last
  // frame that located them (tag_stride).
  FrameRegistration Fit(
      const cv::Mat& luma,
      const std::optional<std::array<Eigen::Vector2d, 4>>& corners,
      bool tag_looked_for);
  // Whether the last still_frames registrations say the camera is still.
  bool Still() const;
  // Keeps a frame's registration for the next frame's start and Still().
  void Remember(const FrameRegistration& r);

  Camera camera_;  // intrinsics only: distortion and projection
  BenchRegistrationOptions options_;
  std::optional<TagReference> tag_;
  std::array<Eigen::Vector3d, 4> tag_rays_;
  std::array<Eigen::Vector2d, 4> last_corners_;
  StaticPatches patches_;
  std::vector<Eigen::Vector3d> patch_rays_;
  CameraMotion last_motion_;
  // The shifts of the last registered frames (at most still_frames + 1),
  // cleared by a frame not registered; frames since the tag was looked for.
  std::vector<Eigen::Vector2d> recent_shifts_px_;
  int frames_since_tag_ = 0;
  std::unique_ptr<TagDetector> detector_;  // made when first needed
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_BENCH_REGISTRATION_H_
