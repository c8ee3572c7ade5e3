#ifndef SOFTBENCH_VISION_STATIC_PATCHES_H_
#define SOFTBENCH_VISION_STATIC_PATCHES_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vision/color_transfer.h"

namespace softbench {

struct StaticPatchOptions {
  // Patches are taken one per cell of this side [px] at most (the strongest
  // structure in it), so they spread over the frame: together they give the
  // camera's motion a lever of the whole image, where one tag gives a few
  // per cent of it. (BenchRegistration scales it for frames above 1080p.)
  double cell_px = 48.0;
  int max_patches = 160;
  // Half side of a patch [px] (a 17 x 17 template).
  int half_size_px = 8;
  // Least RMS luma slope [8-bit levels per px] a patch needs, across its
  // edge (an edge patch: the ring's rim, a mount's side, measured across it
  // only) or in its weaker direction too (a corner patch: measured in both).
  // Weak texture, such as table grain, is what a video codec smooths,
  // freezes and redraws a few tenths of a pixel away at each key frame.
  double min_slope_dn_per_px = 8.0;
  // Gauss-Newton steps per patch and frame; a step below this ends them.
  int max_iterations = 12;
  double tolerance_px = 1e-3;
  // Largest RMS difference between a patch and its template after the
  // photometric fit, relative to the template's own RMS contrast: more means
  // something covers it or it is not the same surface.
  double max_relative_residual = 0.25;
  // How the luma's codes encode light (FrameSource::luma_encoding): the
  // templates and the alignment work in linear light, where a pixel is the
  // light it gathered, so a fraction-of-a-pixel move of an edge changes its
  // pixels as interpolation assumes (in codes a transfer curve bends the
  // edge's profile, and the alignment's bias follows the sub-pixel phase),
  // and exposure is exactly a gain. The patches are chosen by their slope
  // in codes, so the choice does not depend on the curve.
  LumaEncoding luma_encoding;

  std::optional<std::string> Problem() const;
};

// One patch in one frame.
struct PatchMatch {
  bool found = false;
  Eigen::Vector2d reference_px = Eigen::Vector2d::Zero();  // template centre
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();         // where it is now
  // An edge patch's unit normal: only the motion along it is measured.
  // Zero for a corner patch (both directions measured).
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
};

// Small strongly structured patches of a reference frame (the ring's rim,
// mounts, screws, printed marks), followed in later frames to a few
// hundredths of a pixel by Lucas-Kanade alignment against their reference
// templates: a shift (along the normal only, for a straight edge, which
// shows no motion along itself) plus a gain and an offset, so auto-exposure
// does not move them. Aligning against the reference, not the last frame,
// never accumulates drift. Which patches are really static is for the
// caller's robust fit to decide; a mask keeps the mechanism out from the
// start.
class StaticPatches {
 public:
  // `luma` 8 or 16-bit (luma.h); `allowed` CV_8UC1 of the same size (non-zero
  // where a patch may be taken) or empty for anywhere.
  StaticPatches(const cv::Mat& luma, const cv::Mat& allowed,
                const StaticPatchOptions& options = {});

  int size() const { return static_cast<int>(templates_.size()); }

  // Aligns every patch in `luma`, starting each at `predicted[i]` (pixels;
  // e.g. the reference position moved by the last frame's camera motion).
  std::vector<PatchMatch> Track(
      const cv::Mat& luma, const std::vector<Eigen::Vector2d>& predicted) const;

  std::vector<Eigen::Vector2d> reference_px() const;

 private:
  struct Template {
    Eigen::Vector2d centre;
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();  // edge patches
    // Row by row, (2 h + 1)^2 each: the template's linear light and the
    // shift part of the residual's unit-gain Jacobian, its slope in x and y
    // (for an edge: across it in slope_x, zero in slope_y). Flat float
    // arrays, so the sums over a patch are vectorised.
    std::vector<float> values, slope_x, slope_y;
    double contrast = 0.0;  // RMS about the mean
    // The alignment's normal matrix at unit gain, the sum of j j^T over the
    // patch (Jacobian): a change of gain only scales it, so it is summed
    // once.
    Eigen::Matrix4d normal_matrix = Eigen::Matrix4d::Identity();
  };
  // Buffers Align reuses from patch to patch (Track keeps one per thread).
  struct Scratch {
    std::vector<float> light;     // the (2 h + 2)^2 pixels under a patch
    std::vector<float> residual;  // (2 h + 1)^2
  };
  bool Align(const cv::Mat& luma, const Template& t, Scratch* scratch,
             Eigen::Vector2d* centre) const;
  // The unit-gain Jacobian of the residual at template pixel i (row-major).
  static Eigen::Vector4d Jacobian(const Template& t, int i);

  StaticPatchOptions options_;
  std::vector<Template> templates_;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_STATIC_PATCHES_H_
