#ifndef SOFTBENCH_VISION_PLATE_POSE_H_
#define SOFTBENCH_VISION_PLATE_POSE_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "vision/plane_mapping.h"

namespace softbench {

// A head's plate out of the dot plane (issue 27): the thesis measures the
// heads with one camera from above and names their motion toward it as an
// error it could not remove (section 4.2). A plate raised by h looks bigger
// by H / (H - h) and shifted away from the camera's foot; tilted, its dots
// rise unevenly. Its dots through the plane's mapping against the same
// dots at rest give its pose: the lift, the two tilts, and its true
// in-plane position.
struct PlatePoseOptions {
  // Prior standard deviation of each tilt about zero [rad] (a bench's
  // heads tilt by a degree or so). Off the camera's axis perspective shows
  // a tilt to first order and the prior does not matter; on the axis only
  // as the plate's foreshortening (1 - cos, to second order), where the
  // dots' noise alone would otherwise be read as a tilt of degrees and
  // bias the lift up.
  double tilt_prior_rad = 0.02;
  // Solver iterations. Off the camera's axis a plate within a few degrees
  // of rest converges in a few; near the axis, where the tilts show only to
  // second order, convergence is linear and the bench's samples take up to
  // 260 (30 left 15 of the delta sample's 3420 frames unconverged, their
  // lifts up to 0.07 mm off the minimum).
  int max_iterations = 300;

  std::optional<std::string> Problem() const;
};

// The pose of a plate against its rest, in the dot plane's frame.
struct PlatePose {
  // The solver ended at a usable pose: converged, or out of iterations
  // (near the camera's axis the tilt converges slowly; the lift and
  // centre do not depend on its last digits). why_not when not.
  bool found = false;
  std::string why_not;
  // Rise of the plate's centre toward the camera [mm].
  double lift_mm = 0.0;
  // The plate's turn out of the plane: the in-plane part (about world y,
  // about world z) of its rotation vector [rad]; a point at offset (a, b)
  // from the centre rises by about tilt_y b - tilt_z a.
  Eigen::Vector2d tilt_rad = Eigen::Vector2d::Zero();
  // Its turn in the plane (the rotation vector's normal part) [rad].
  double rotation_rad = 0.0;
  // Where the plate's rest centre (the mean of its rest dots) now is, on
  // the plane [mm]: the head's position with the parallax taken out.
  Eigen::Vector2d centre_mm = Eigen::Vector2d::Zero();
  // The apparent centre (the mean of the dots as mapped) less the true one
  // [mm]: what the lift and tilt added to the measured position.
  Eigen::Vector2d parallax_mm = Eigen::Vector2d::Zero();
};

// The dots of a plate posed by (centre, lift, tilt, rotation) as the
// plane's mapping shows them, from its dots at rest (on the plane, flat).
std::vector<Eigen::Vector2d> ApparentDots(
    const std::vector<Eigen::Vector2d>& rest_dots_mm,
    const CameraAbovePlane& camera, const Eigen::Vector2d& centre_mm,
    double lift_mm, const Eigen::Vector2d& tilt_rad, double rotation_rad);

// The pose that shows `dots_mm` (the same dots as `rest_dots_mm`, in the
// same order, through the plane's mapping), by least squares with a prior
// on the tilts. Needs two dots or more (with two, the tilts rest on their
// prior). `dot_sigma_mm` (> 0) is one dot coordinate's standard error on
// the plane, which weighs the tilts' prior against the dots: `validate`
// sets it from the footage's scale (VideoMeasurementOptions::
// plate_dot_sigma_px). Set below what the footage leaves in the dots, it
// lets their errors pass for a tilt; near the camera's axis a tilt shows
// only as foreshortening, which the lift then makes up, so the lift is
// biased up (docs/measurement.md).
PlatePose FitPlatePose(const std::vector<Eigen::Vector2d>& rest_dots_mm,
                       const std::vector<Eigen::Vector2d>& dots_mm,
                       const CameraAbovePlane& camera, double dot_sigma_mm,
                       const PlatePoseOptions& options = {});

// The lift's standard deviation [mm] from each dot's own error: every
// coordinate of every dot independent with standard deviation
// `dot_sigma_mm`, propagated through FitPlatePose at rest with the dots
// weighed at `fit_dot_sigma_mm`, as the lift was measured. A phone's
// sharpening moves each dot's centre by a few hundredths of a pixel with
// its pixel phase, and the dots' spacing, which the lift is read from,
// moves with them (docs/uncertainty.md). NaN when a fit fails.
double LiftSigmaFromDots(const std::vector<Eigen::Vector2d>& rest_dots_mm,
                         const CameraAbovePlane& camera, double dot_sigma_mm,
                         double fit_dot_sigma_mm,
                         const PlatePoseOptions& options = {});

}  // namespace softbench

#endif  // SOFTBENCH_VISION_PLATE_POSE_H_
