#ifndef SOFTBENCH_PIPELINES_VALIDATION_UNCERTAINTY_BUDGET_H_
#define SOFTBENCH_PIPELINES_VALIDATION_UNCERTAINTY_BUDGET_H_

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

namespace softbench {

class IntrinsicsSensitivity;
struct VideoMeasurement;
struct WindowSummary;

// One source of error in a measured change of a head's position.
struct UncertaintyTerm {
  // "window scatter", "dots", "codec", "scale", "intrinsics", "parallax"
  std::string name;
  // Standard uncertainty of the change's y and z [mm].
  Eigen::Vector2d u_mm = Eigen::Vector2d::Zero();
};

// The standard uncertainty of a change of a head's position between two
// windows (a displacement, or a hysteresis), term by term (GUM: independent
// terms in quadrature). docs/uncertainty.md derives each term.
struct UncertaintyBudget {
  std::vector<UncertaintyTerm> terms;
  Eigen::Vector2d u_mm = Eigen::Vector2d::Constant(NAN);  // per axis

  // The two axes in quadrature [mm]: the standard uncertainty of the
  // change's length in the sense that a two-dimensional normal error lies
  // within it 63 % of the time and within 2u 98 % of the time.
  double TotalMm() const { return u_mm.norm(); }
  // The name of the term with the largest share, or "" without terms.
  std::string Largest() const;
};

// What every change of one head in a video shares.
struct HeadUncertaintyContext {
  // How far the head's dots disagree about a change once the head's own
  // motion (shift, turn and the scale of a lift) is taken out, pooled over the
  // video's changes: one dot's standard uncertainty per axis [mm], and the
  // degrees of freedom behind it (0: not estimable, fewer than three dots).
  double dot_sigma_mm = 0.0;
  int dot_dof = 0;
  // The codec's error in a window's position, per axis [mm^2]: a still
  // head's image is drawn afresh at each I picture and repeated, errors
  // and all, until the next, so the window's frames share one error. Its
  // variance is half the mean square jump of a still head's position at
  // the I pictures (StillIntraJumps), `codec_jumps` of them (0: not
  // estimable).
  Eigen::Vector2d codec_level_mm2 = Eigen::Vector2d::Zero();
  int codec_jumps = 0;
  // The relative standard uncertainty of the dot plane's scale: how far the
  // dots' spacing, measured through the mapping in each window, is from the
  // plan's layout (the median offset, and the median's standard error),
  // whether from the tag's size and pose, the lens or the camera's
  // distance. It scales a change's length.
  double scale_relative = 0.0;
  // How the mapping depends on the intrinsics' standard errors (not owned;
  // null or not Known(): no term), and the head's rest position [mm, plane
  // coordinates] that the windows' displacements are from.
  const IntrinsicsSensitivity* intrinsics = nullptr;
  Eigen::Vector2d rest_mm = Eigen::Vector2d::Zero();
  // Whether the positions still carry the parallax of the head's lift and
  // tilt (validate without --lift-correction). Then the parallax measured
  // between the two windows is a known error left in the change, and its
  // size per axis is a term (GUM F.2.4.5: an uncorrected systematic effect
  // enlarges the uncertainty): a lifting head's displacement keeps a U
  // that covers it, and a flat head's term is the lift's noise through its
  // lever, which one camera cannot tell from a lift.
  bool parallax_in_positions = false;
};

// HeadUncertaintyContext::scale_relative from the windows' dot medians of
// head `h` against its plan `layout_mm`; 0 without windows with dots.
double LayoutScaleUncertainty(const std::vector<const WindowSummary*>& windows,
                              int h,
                              const std::vector<Eigen::Vector2d>& layout_mm);

// Consecutive positions of a head within this [px] of each other are a
// head at rest (a settling head moves 0.03 px a frame 1 s after a 1 mm step).
inline constexpr double kStillPx = 0.05;

// How far head `h`'s positions may range over a few consecutive frames and
// still be a head at rest [mm]: kStillPx at the measurement's scale, or,
// where single frames scatter more than that, 6 times their scatter (8
// frames of Gaussian noise range further once in a thousand). A phone's
// noise and sharpening and what registration leaves of a trembling tripod
// scatter a still head's frames by 0.02-0.05 px (`render --isp
// --camera-tremor-px 0.1 --rolling-shutter-ms 20`), and with kStillPx alone
// no I picture of such footage had a still head on both sides, so the
// codec's term went unmeasured. The scatter per frame is taken robustly
// from the second differences of consecutive positions (1.4826 times their
// median absolute value over sqrt(6)), which a steady motion does not
// enter and the video's moving frames, a minority, do not move.
double StillRangeMm(const VideoMeasurement& measurement, int h);

// How far head `h`'s position jumps at each I picture of `measurement`
// around which it is still [mm]: the median of the frames from the I
// picture on less that of the frames before it, each side 3 to 8
// consecutive frames with the head complete, none of them
// another I picture, and each side within StillRangeMm on both axes; a
// jump of more than 10 kStillPx is a head that moved between two frames,
// not the codec, and is left out.
// Every still I picture of the video counts where every frame was read:
// the more states of the codec it sees, the less it depends on where the
// I pictures fall against the windows (a plan whose period is a multiple
// of the key-frame interval puts them at the same place in every test).
// With the jump of the head's position, that of its lift toward the camera
// [mm] (NaN where the frames have none).
struct IntraJump {
  Eigen::Vector2d position_mm;
  double lift_mm = NAN;
};
std::vector<IntraJump> StillIntraJumps(const VideoMeasurement& measurement,
                                       int h);

// The codec's error in one window's position, pooled over a video's heads:
// the variance per axis [mm^2], half the mean square of StillIntraJumps
// (a jump is the difference of two independent levels, the one the codec
// repeated before the I picture and the one after), and how many jumps it
// rests on (0: not measured).
struct CodecLevel {
  Eigen::Vector2d variance_mm2 = Eigen::Vector2d::Zero();
  int jumps = 0;
  // The same for a window's lift [mm^2] (issue 27), from the jumps that
  // have one.
  double lift_variance_mm2 = 0.0;
};
CodecLevel MeasureCodecLevel(const VideoMeasurement& measurement);

// The dots' disagreement about the change from `from` to `to` for head `h`:
// the residual sum of squares [mm^2] of a similarity fit (shift, small
// turn and change of scale) to the dots' changes, and its degrees of
// freedom (2 n - 4; 0 with fewer than three dots or a window without
// them). The scale is fitted because a head's lift toward the camera
// scales its dots (h / H); a rigid fit counted that as the dots' error.
struct SimilarityResidual {
  double sum_of_squares_mm2 = 0.0;
  int dof = 0;
};
SimilarityResidual DotsSimilarityResidual(const WindowSummary& from,
                                          const WindowSummary& to, int h);
// The same for two sets of the same dots (in the same order).
SimilarityResidual DotsSimilarityResidual(
    const std::vector<Eigen::Vector2d>& from,
    const std::vector<Eigen::Vector2d>& to);

// The standard uncertainty of head `h`'s position in one frame against its
// rest position, per axis [mm], from what needs no windows (track's
// trajectory): the codec's level in the frame and at rest, the frames'
// own scatter (half the mean square step between consecutive frames of a
// still head, not across an I picture), and the dots' disagreement against
// the first frame that has them all, pooled over the video. `codec` is
// MeasureCodecLevel(measurement), measured once for every head.
Eigen::Vector2d FrameUncertaintyMm(const VideoMeasurement& measurement,
                                   const CodecLevel& codec, int h);

// The budget of head `h`'s change from window `from` to window `to`.
UncertaintyBudget ChangeBudget(const WindowSummary& from,
                               const WindowSummary& to, int h,
                               const HeadUncertaintyContext& context);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_VALIDATION_UNCERTAINTY_BUDGET_H_
