#ifndef SOFTBENCH_VISION_ROLLING_SHUTTER_H_
#define SOFTBENCH_VISION_ROLLING_SHUTTER_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "vision/camera_motion.h"

namespace softbench {

// What one frame's registration says of a rolling shutter's shear. A
// rolling shutter reads each line at its own time, so a camera that moves
// at v [px/s] moves a point on a line a fraction s from the frame's middle
// line (-1/2 at the first line, +1/2 at the last) by s T v, T the readout.
// Basis k of the four is that displacement for T v the unit vector k % 2
// (x, y), with s from the point's row (k < 2: the lines are the upright
// picture's rows) or its column (k >= 2: a portrait video's sensor), as a
// misfit (along an edge patch's normal), less the part the frame's fitted
// motion (pan, tilt and, where fitted, roll and scale) takes up.
struct ShutterShearSums {
  Eigen::Vector4d misfit_dot_basis = Eigen::Vector4d::Zero();  // [px]
  Eigen::Matrix4d basis_gram = Eigen::Matrix4d::Zero();        // [1]
  // How the fitted motion's parameters (rotation vector [rad], log scale)
  // took up each basis: column k is their change for a unit of basis k.
  Eigen::Matrix4d motion_from_basis = Eigen::Matrix4d::Zero();
};

struct RollingShutterOptions {
  // The camera's image velocity at a frame comes from the registered shifts
  // of the frames up to this many either side (all registered, evenly
  // spaced in time) through a Hann-windowed ideal differentiator: at 8 it
  // is within 1 % of the true velocity up to 0.8 of the frame rate's
  // Nyquist frequency (a tripod's tremor, 2-12 Hz, at 30 fps), where a
  // central difference reads a 12 Hz tremor's velocity at a quarter.
  int velocity_half_frames = 8;
  // The frames' sums are pooled in blocks of this many for the readout's
  // standard error: neighbouring frames share their tremor and the codec's
  // errors on the static points.
  int block_frames = 15;
  // Fewest blocks for a standard error (a sandwich over fewer says little).
  int min_blocks = 6;
  // Added in quadrature to the readout's standard error [s]: the static
  // points' tracking leaves an apparent readout of its own under 0.3 px of
  // tremor, of either sign and several of the sandwich's standard errors:
  // on rendered global-shutter frames -0.8 ms (1080p) and +1.1 / +2.5 ms
  // (720p, rows / columns), on 1080p H.264 at CRF 17 -1.5 / -2.1 ms; a
  // 30 ms readout there reads 27.3 ms (docs/measurement.md).
  double systematic_s = 0.002;
  // The readout is reported only when known to this standard error [s] or
  // better: a still camera's image does not move, and shows no shear.
  double max_standard_error_s = 0.004;
  // A rolling shutter is named when its readout is this many standard
  // errors from zero: a phone reads its sensor in 10-30 ms, and with
  // systematic_s a readout from about 9 ms is named.
  double min_significance = 4.0;

  std::optional<std::string> Problem() const;
};

// A rolling shutter measured from the registration's misfits.
struct RollingShutter {
  bool measured = false;
  std::string why_not;  // when !measured
  int frames = 0;       // frames whose velocity was known
  // The readout along the direction the lines go, first to last [s], for
  // lines that are the upright picture's rows (top first: positive) and
  // its columns (left first: positive); with standard errors.
  // The standard errors include options.systematic_s.
  double rows_readout_s = 0.0, rows_standard_error_s = 0.0;
  double columns_readout_s = 0.0, columns_standard_error_s = 0.0;
  bool seen = false;    // a readout passed the options' bars
  bool by_rows = true;  // which of the two is the shutter's (the larger z)
  // The RMS over the frames of readout x image speed: how far the camera
  // moved the image between reading the first line and the last [px].
  double shear_rms_px = 0.0;

  double readout_s() const {
    return by_rows ? rows_readout_s : columns_readout_s;
  }
  double standard_error_s() const {
    return by_rows ? rows_standard_error_s : columns_standard_error_s;
  }
  // How much later than the frame's time (its middle line's) the line
  // through `pixel` was read [s], in a frame `frame_size_px` wide and high;
  // zero unless seen.
  double ReadDelayS(const Eigen::Vector2d& pixel,
                    const Eigen::Vector2d& frame_size_px) const;
  // The camera's motion at the frame's time (its middle line's) from the
  // motion its registration fitted, which took up part of the shear of a
  // camera moving the image at `velocity_px_s` (sums.motion_from_basis);
  // `fitted` unless seen.
  CameraMotion MiddleLineMotion(const CameraMotion& fitted,
                                const ShutterShearSums& sums,
                                const Eigen::Vector2d& velocity_px_s) const;
  // One line for a person.
  std::string Summary() const;
};

// A video's frames as their registrations saw them, one entry per frame
// in each (ImageVelocities need no `sums`).
struct RegisteredFrames {
  std::vector<double> times_s;
  // The image's shift at the principal point since the reference frame, as
  // each frame's registration fitted it [px].
  std::vector<Eigen::Vector2d> shifts_px;
  std::vector<ShutterShearSums> sums;
  std::vector<int64_t> index;    // consecutive frames differ by one
  std::vector<bool> registered;  // false: the entries above mean nothing
};

// The camera's image velocity at each frame [px/s] from the registered
// shifts of its neighbours (velocity_half_frames either side, all
// registered, consecutive and evenly spaced), else nullopt.
std::vector<std::optional<Eigen::Vector2d>> ImageVelocities(
    const RegisteredFrames& frames, const RollingShutterOptions& options = {});

// The readout fitted to the sums of every frame whose velocity is known
// (`velocities`, one per frame: ImageVelocities of `frames` with the same
// options), with a shear pattern common to all frames (the reference
// frame's own, a lens model's error) taken out.
RollingShutter EstimateRollingShutter(
    const RegisteredFrames& frames,
    const std::vector<std::optional<Eigen::Vector2d>>& velocities,
    const RollingShutterOptions& options = {});

}  // namespace softbench

#endif  // SOFTBENCH_VISION_ROLLING_SHUTTER_H_
