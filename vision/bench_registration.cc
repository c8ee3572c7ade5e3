#include "vision/bench_registration.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "util/check.h"
#include "util/statistics.h"
#include "vision/frame_source.h"

namespace softbench {

std::optional<std::string> BenchRegistrationOptions::Problem() const {
  if (auto problem = tag.Problem()) return problem;
  if (auto problem = patches.Problem()) return problem;
  if (max_refits < 1) return "max_refits must be >= 1";
  if (!(refit_tolerance_px > 0.0)) return "refit_tolerance_px must be > 0";
  if (!(max_edge_rms_px > 0.0)) return "max_edge_rms_px must be > 0";
  if (!(outlier_px > 0.0)) return "outlier_px must be > 0";
  if (min_patches < 3) return "min_patches must be >= 3";
  if (min_patches_for_scale < min_patches) {
    return "min_patches_for_scale must be >= min_patches";
  }
  if (!(max_residual_px > 0.0)) return "max_residual_px must be > 0";
  if (tag_stride < 1) return "tag_stride must be >= 1";
  if (still_frames < 2) return "still_frames must be >= 2";
  if (!(still_tremor_px >= 0.0)) return "still_tremor_px must be >= 0";
  if (!(still_step_px > 0.0)) return "still_step_px must be > 0";
  return std::nullopt;
}

namespace {

// How far a point may be from the robust start's motion [px] to join the
// fit: a bump's roll moves far points differently by up to about this.
constexpr double kStartGatePx = 1.5;

// FitMotion's forward-difference step in its parameters: 1e-6 rad moves
// a point by a few thousandths of a pixel.
constexpr double kStep = 1e-6;

// A motion's parameters as FitMotion fits them: the rotation vector (pan,
// tilt, roll) and the log of the scale.
Eigen::Vector4d ParametersOf(const CameraMotion& motion) {
  Eigen::Vector4d p;
  p << motion.rotation_rad, std::log(motion.scale);
  return p;
}

Eigen::Matrix3d CurrentFromReferenceOf(const Eigen::Vector4d& p) {
  CameraMotion m;
  m.rotation_rad = p.head<3>();
  m.scale = std::exp(p[3]);
  return m.CurrentFromReference();
}

// The motion's matrix at parameters p (m[0]) and at p + kStep along each
// of the first `moved` (m[k + 1]): a Jacobian by forward differences.
std::array<Eigen::Matrix3d, 5> Stepped(const Eigen::Vector4d& p, int moved) {
  std::array<Eigen::Matrix3d, 5> m;
  m[0] = CurrentFromReferenceOf(p);
  for (int k = 0; k < moved; ++k) {
    m[k + 1] = CurrentFromReferenceOf(p + kStep * Eigen::Vector4d::Unit(k));
  }
  return m;
}

const BenchRegistrationOptions& Checked(const BenchRegistrationOptions& o) {
  // A programmer error: options come from code, not from users.
  SOFTBENCH_CHECK(!o.Problem()) << *o.Problem();
  return o;
}

// Patches may be taken where the scene is static, but not on the tag: its
// corners stand for it, and its strong bits would draw every patch to it.
cv::Mat PatchMask(const cv::Mat& static_mask, const cv::Size& size,
                  const std::optional<TagReference>& tag) {
  cv::Mat mask = static_mask.empty() ? cv::Mat(size, CV_8UC1, cv::Scalar(255))
                                     : static_mask.clone();
  if (tag) {
    const double side_px = (tag->corners[0] - tag->corners[2]).norm();
    const cv::Rect box = BoxAround({tag->corners.begin(), tag->corners.end()},
                                   0.5 * side_px, size);
    if (!box.empty()) mask(box).setTo(0);
  }
  return mask;
}

// Patches are spread one per cell of a 1080p frame's size: a larger frame
// gets larger cells (the same structure spans more pixels), so a 4K frame
// follows as many patches as a 1080p one, each to the same fraction of a
// millimetre.
StaticPatchOptions ScaledToFrame(StaticPatchOptions options,
                                 const cv::Size& size) {
  options.cell_px *= std::max(
      1.0, std::sqrt(static_cast<double>(size.area()) / (1920 * 1080)));
  return options;
}

}  // namespace

BenchRegistration::BenchRegistration(const CameraIntrinsics& intrinsics,
                                     const cv::Mat& reference_luma,
                                     const cv::Mat& static_mask,
                                     const std::optional<TagReference>& tag,
                                     const BenchRegistrationOptions& options)
    : camera_(intrinsics, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()),
      options_(Checked(options)),
      tag_(tag),
      patches_(reference_luma,
               PatchMask(static_mask, reference_luma.size(), tag),
               ScaledToFrame(options.patches, reference_luma.size())) {
  if (tag_) {
    for (int c = 0; c < 4; ++c) {
      tag_rays_[c] = camera_.Undistort(tag_->corners[c]).homogeneous();
    }
  }
  for (const Eigen::Vector2d& p : patches_.reference_px()) {
    patch_rays_.emplace_back(camera_.Undistort(p).homogeneous());
  }
  Restart();  // the one place that knows a fresh registration's state
}

BenchRegistration::BenchRegistration(const BenchRegistration& other)
    : camera_(other.camera_),
      options_(other.options_),
      tag_(other.tag_),
      tag_rays_(other.tag_rays_),
      last_corners_(other.last_corners_),
      patches_(other.patches_),
      patch_rays_(other.patch_rays_),
      last_motion_(other.last_motion_),
      recent_shifts_px_(other.recent_shifts_px_),
      frames_since_tag_(other.frames_since_tag_) {}

std::unique_ptr<BenchRegistration> BenchRegistration::Clone() const {
  return std::unique_ptr<BenchRegistration>(new BenchRegistration(*this));
}

void BenchRegistration::Restart() {
  if (tag_) last_corners_ = tag_->corners;
  last_motion_ = CameraMotion();
  recent_shifts_px_.clear();
  frames_since_tag_ = 0;
}

Eigen::Vector2d BenchRegistration::Predict(
    const Eigen::Matrix3d& current_from_reference,
    const Eigen::Vector3d& ray) const {
  const Eigen::Vector3d n = current_from_reference * ray;
  return camera_.Distort(n.head<2>() / n.z());
}

Eigen::Vector2d BenchRegistration::Misfit(
    const Eigen::Matrix3d& current_from_reference, const Point& p) const {
  Eigen::Vector2d d = Predict(current_from_reference, p.ray) - p.pixel;
  if (p.normal == Eigen::Vector2d::Zero()) return d;
  return {p.normal.dot(d), 0.0};
}

double BenchRegistration::FitMotion(const std::vector<Point>& points,
                                    const std::vector<double>& weights,
                                    int parameters,
                                    CameraMotion* motion) const {
  // Parameters: the rotation vector (pan, tilt, roll) and the log of the
  // scale; those past `parameters` are held at their start. Gauss-Newton
  // with forward differences: the model is smooth and cheap, and 1e-6 rad
  // moves a point by a few thousandths of a pixel. The Jacobian's error
  // (about 1e-6 of it) only slows the convergence; where it stops, at a
  // step under 1e-12, is set by the residuals, which are exact. Central
  // differences cost nearly twice the evaluations for the same answer.
  // The normal equations are summed point by point in fixed-size matrices:
  // this runs several times for every frame, and a residual vector and a
  // Jacobian on the heap for each evaluation cost as much as the sums.
  Eigen::Vector4d p = ParametersOf(*motion);
  // The weighted sum of squared misfits at `p`; with `normal` and
  // `gradient`, also J'J and J'r over the first `parameters` (the others'
  // rows are the identity's and zero, so their step is zero).
  const auto sums = [&](Eigen::Matrix4d* normal, Eigen::Vector4d* gradient) {
    const int moved = normal != nullptr ? parameters : 0;
    const SteppedMatrices m = Stepped(p, moved);
    if (normal != nullptr) {
      normal->setZero();
      gradient->setZero();
    }
    double squares = 0.0;
    for (size_t i = 0; i < points.size(); ++i) {
      if (weights[i] == 0.0) continue;
      const double root = std::sqrt(weights[i]);
      const Eigen::Vector2d r = root * Misfit(m[0], points[i]);
      squares += r.squaredNorm();
      if (normal == nullptr) continue;
      const Eigen::Matrix<double, 2, 4> jacobian =
          MisfitJacobian(m, moved, points[i], r, root);
      *normal += jacobian.transpose() * jacobian;
      *gradient += jacobian.transpose() * r;
    }
    if (normal != nullptr) {
      for (int k = moved; k < 4; ++k) (*normal)(k, k) = 1.0;
    }
    return squares;
  };
  Eigen::Matrix4d normal;
  Eigen::Vector4d gradient;
  for (int iteration = 0; iteration < 10; ++iteration) {
    sums(&normal, &gradient);
    const Eigen::Vector4d delta = normal.ldlt().solve(-gradient);
    p += delta;
    if (delta.lpNorm<Eigen::Infinity>() < 1e-12) break;
  }
  const double squares = sums(nullptr, nullptr);
  motion->rotation_rad = p.head<3>();
  motion->scale = std::exp(p[3]);
  double used = 0.0;
  for (double w : weights) used += w;
  return std::sqrt(squares / std::max(used, 1.0));
}

Eigen::Matrix<double, 2, 4> BenchRegistration::MisfitJacobian(
    const SteppedMatrices& m, int moved, const Point& p,
    const Eigen::Vector2d& misfit, double root) const {
  Eigen::Matrix<double, 2, 4> jacobian = Eigen::Matrix<double, 2, 4>::Zero();
  for (int k = 0; k < moved; ++k) {
    jacobian.col(k) = (root * Misfit(m[k + 1], p) - misfit) / kStep;
  }
  return jacobian;
}

ShutterShearSums BenchRegistration::ShearSums(
    const std::vector<Point>& points, const std::vector<double>& weights,
    int parameters, const CameraMotion& motion, const cv::Size& size) const {
  // The normal equations of the fitted parameters (J'J), of the shear
  // bases against them (J'B) and against themselves (B'B), and of the
  // misfits (J'r, B'r), over the points kept; the bases' and misfits'
  // parts along the fit are taken out through J'J (ShutterShearSums).
  const SteppedMatrices m = Stepped(ParametersOf(motion), parameters);
  Eigen::Matrix4d jtj = Eigen::Matrix4d::Zero(), jtb = jtj, btb = jtj;
  Eigen::Vector4d jtr = Eigen::Vector4d::Zero(), btr = jtr;
  for (size_t i = 0; i < points.size(); ++i) {
    if (weights[i] == 0.0) continue;
    const Point& p = points[i];
    const Eigen::Vector2d r = Misfit(m[0], p);
    const Eigen::Matrix<double, 2, 4> j = MisfitJacobian(m, parameters, p, r);
    // The point's line, from -1/2 (first) to +1/2 (last), as a row or a
    // column; a later line sees the camera later, so the point is seen
    // moved by s T v and the prediction misses it by minus that.
    const Eigen::Vector2d s((p.pixel.y() + 0.5) / size.height - 0.5,
                            (p.pixel.x() + 0.5) / size.width - 0.5);
    Eigen::Matrix<double, 2, 4> basis;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d moved = -s[k / 2] * Eigen::Vector2d::Unit(k % 2);
      basis.col(k) = p.normal == Eigen::Vector2d::Zero()
                         ? moved
                         : Eigen::Vector2d(p.normal.dot(moved), 0.0);
    }
    jtj += j.transpose() * j;
    jtb += j.transpose() * basis;
    btb += basis.transpose() * basis;
    jtr += j.transpose() * r;
    btr += basis.transpose() * r;
  }
  for (int k = parameters; k < 4; ++k) jtj(k, k) = 1.0;
  const auto solver = jtj.ldlt();
  ShutterShearSums sums;
  // The fit moves its parameters by -(J'J)^-1 J'B per unit of the bases.
  sums.motion_from_basis = -solver.solve(jtb);
  sums.basis_gram = btb + jtb.transpose() * sums.motion_from_basis;
  sums.misfit_dot_basis = btr - jtb.transpose() * solver.solve(jtr);
  return sums;
}

std::optional<std::array<Eigen::Vector2d, 4>> BenchRegistration::Follow(
    const cv::Mat& luma, std::array<Eigen::Vector2d, 4> start) const {
  for (int refit = 0; refit < options_.max_refits; ++refit) {
    const auto corners =
        RefineTagCorners(luma, start, options_.tag, options_.max_edge_rms_px);
    if (!corners) return std::nullopt;
    const double moved = LargestCornerMove(*corners, start);
    start = *corners;
    if (moved < options_.refit_tolerance_px) break;
  }
  return start;
}

std::optional<std::array<Eigen::Vector2d, 4>> BenchRegistration::FindTag(
    const cv::Mat& luma) {
  if (!tag_) return std::nullopt;
  if (auto corners = Follow(luma, last_corners_)) return corners;
  if (LargestCornerMove(last_corners_, tag_->corners) > 0.0) {
    if (auto corners = Follow(luma, tag_->corners)) return corners;
  }
  // A bump beyond the edge profiles: detect the tag afresh near its last
  // position (its box grown by its own size).
  if (detector_ == nullptr) {
    detector_ = std::make_unique<TagDetector>(options_.tag);
  }
  const double side_px = (last_corners_[0] - last_corners_[2]).norm();
  const cv::Rect region = BoxAround(
      {last_corners_.begin(), last_corners_.end()}, side_px, luma.size());
  if (region.empty()) return std::nullopt;
  for (TagDetection d : detector_->Detect(luma(region))) {
    if (d.id != tag_->id || !d.refined) continue;
    for (Eigen::Vector2d& corner : d.corners) {
      corner += Eigen::Vector2d(region.x, region.y);
    }
    return Follow(luma, d.corners);
  }
  return std::nullopt;
}

std::vector<double> BenchRegistration::MedianMotionWeights(
    const std::vector<Point>& points, const CameraMotion& motion) const {
  const Eigen::Matrix3d current_from_reference = motion.CurrentFromReference();
  std::vector<double> dx, dy;
  for (const Point& p : points) {
    const Eigen::Vector2d d = -Misfit(current_from_reference, p);
    dx.push_back(d.x());
    dy.push_back(d.y());
  }
  const Eigen::Vector2d median(Median(dx), Median(dy));
  std::vector<double> weights(points.size(), 0.0);
  for (size_t i = 0; i < points.size(); ++i) {
    weights[i] = (Eigen::Vector2d(dx[i], dy[i]) - median).norm() <= kStartGatePx
                     ? 1.0
                     : 0.0;
  }
  return weights;
}

double BenchRegistration::FitWithinGates(const std::vector<Point>& points,
                                         bool tag_found,
                                         std::vector<double>* weights,
                                         CameraMotion* motion,
                                         FrameRegistration* out) const {
  double rms = 0.0;
  for (const double gate : {kStartGatePx, options_.outlier_px}) {
    bool tag_kept = true;
    const Eigen::Matrix3d current_from_reference =
        motion->CurrentFromReference();
    for (size_t i = 0; i < points.size(); ++i) {
      const double r = Misfit(current_from_reference, points[i]).norm();
      (*weights)[i] = r <= gate ? 1.0 : 0.0;
      if (points[i].tag_corner && (*weights)[i] == 0.0) tag_kept = false;
    }
    out->tag_used = tag_found && tag_kept;
    out->patches_used = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      // The tag counts whole or not at all.
      if (points[i].tag_corner && !out->tag_used) (*weights)[i] = 0.0;
      if (!points[i].tag_corner && (*weights)[i] > 0.0) ++out->patches_used;
    }
    if (!out->tag_used && out->patches_used < options_.min_patches) break;
    out->parameters = out->patches_used >= options_.min_patches_for_scale ? 4
                      : out->patches_used >= options_.min_patches         ? 3
                                                                          : 2;
    rms = FitMotion(points, *weights, out->parameters, motion);
  }
  return rms;
}

FrameRegistration BenchRegistration::Register(const cv::Mat& luma) {
  if (tag_ && frames_since_tag_ + 1 < options_.tag_stride && Still()) {
    // Between the strides: the tag's corners held from the last frame that
    // located them, every patch aligned afresh. A knock moves the patches
    // away from the held corners (and the fit away from the last frame's),
    // and the frame is registered in full instead.
    FrameRegistration held = Fit(luma, last_corners_, false);
    const double step_px =
        (held.shift_px - last_motion_.ShiftPx(camera_.intrinsics())).norm();
    if (held.registered && held.parameters == 4 &&
        step_px <= options_.still_step_px) {
      ++frames_since_tag_;
      Remember(held);
      return held;
    }
  }
  frames_since_tag_ = 0;
  FrameRegistration full = Fit(luma, FindTag(luma), true);
  Remember(full);
  return full;
}

void BenchRegistration::Remember(const FrameRegistration& r) {
  if (!r.registered) {
    recent_shifts_px_.clear();
    return;
  }
  last_motion_ = r.motion;
  if (static_cast<int>(recent_shifts_px_.size()) > options_.still_frames) {
    recent_shifts_px_.erase(recent_shifts_px_.begin());
  }
  recent_shifts_px_.push_back(r.shift_px);
}

bool BenchRegistration::Still() const {
  const int n = static_cast<int>(recent_shifts_px_.size());
  if (n <= options_.still_frames) return false;
  std::array<std::vector<double>, 2> differences;
  for (int i = 1; i < n; ++i) {
    const Eigen::Vector2d d = recent_shifts_px_[i] - recent_shifts_px_[i - 1];
    if (d.norm() > options_.still_step_px) return false;
    for (int c = 0; c < 2; ++c) differences[c].push_back(d[c]);
  }
  for (std::vector<double>& d : differences) {
    const double median = Median(d);
    for (double& v : d) v = std::abs(v - median);
    if (1.4826 * Median(d) / std::sqrt(2.0) > options_.still_tremor_px) {
      return false;
    }
  }
  return true;
}

FrameRegistration BenchRegistration::Fit(
    const cv::Mat& luma,
    const std::optional<std::array<Eigen::Vector2d, 4>>& corners,
    bool tag_looked_for) {
  FrameRegistration out;
  out.tag_skipped = !tag_looked_for;
  std::vector<Point> points;
  // The patches start where the tag says the camera went (their own
  // alignment converges within about a pixel), else where it last was.
  CameraMotion motion = last_motion_;
  if (corners) {
    for (int c = 0; c < 4; ++c) {
      points.push_back(
          {tag_rays_[c], (*corners)[c], true, Eigen::Vector2d::Zero()});
    }
    FitMotion(points, std::vector<double>(4, 1.0), 2, &motion);
  }
  const Eigen::Matrix3d current_from_reference = motion.CurrentFromReference();
  std::vector<Eigen::Vector2d> predicted;
  for (const Eigen::Vector3d& ray : patch_rays_) {
    predicted.push_back(Predict(current_from_reference, ray));
  }
  const std::vector<PatchMatch> matches = patches_.Track(luma, predicted);
  int patches_found = 0;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (!matches[i].found) continue;
    points.push_back(
        {patch_rays_[i], matches[i].pixel, false, matches[i].normal});
    ++patches_found;
  }
  if (!corners && patches_found < options_.min_patches) {
    out.why_not = fmt::format(
        "{}and {} of the {} static patches found (at least {} needed)",
        tag_ ? "the tag's border is covered, shadowed, blurred or out of "
               "view, "
             : "no tag in the plan, ",
        patches_found, patches_.size(), options_.min_patches);
    return out;
  }
  // A robust start: the tag alone when it was found (four corners that
  // belong together: `motion` already), else the points that moved with
  // the median since the last frame (a bump moves them all alike; a moving
  // part does not).
  std::vector<double> weights(points.size(), 0.0);
  if (!corners) {
    weights = MedianMotionWeights(points, motion);
    FitMotion(points, weights, 2, &motion);
  }
  // Then every point near that motion, and again with the final gate.
  const double rms =
      FitWithinGates(points, corners.has_value(), &weights, &motion, &out);
  out.residual_px = rms;
  out.motion = motion;
  if (!out.tag_used && out.patches_used < options_.min_patches) {
    out.why_not = fmt::format(
        "the tag and the static patches do not agree on one camera motion "
        "({} of {} patches consistent)",
        out.patches_used, patches_found);
    return out;
  }
  if (rms > options_.max_residual_px) {
    out.why_not = fmt::format(
        "the static points do not fit one camera motion (RMS {:.2f} px): the "
        "tag or the bench moved, or the frame is blurred",
        rms);
    return out;
  }
  out.registered = true;
  out.shift_px = motion.ShiftPx(camera_.intrinsics());
  out.shear_sums =
      ShearSums(points, weights, out.parameters, motion, luma.size());
  if (out.tag_used && tag_looked_for) {
    out.tag_corners = corners;
    last_corners_ = *corners;
  }
  return out;
}

}  // namespace softbench
