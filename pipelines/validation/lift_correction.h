#ifndef SOFTBENCH_PIPELINES_VALIDATION_LIFT_CORRECTION_H_
#define SOFTBENCH_PIPELINES_VALIDATION_LIFT_CORRECTION_H_

#include <cmath>
#include <optional>
#include <string>

#include "pipelines/validation/validation.h"

namespace softbench {

// Whether validate takes the parallax of the heads' lift and tilt out of
// their positions (issue 27; docs/measurement.md, "Out of the plane").
enum class LiftCorrectionMode {
  kAuto,       // where the measured lifts show the heads leave the plane
  kEveryHead,  // always (--lift-correction)
  kNone,       // never (--no-lift-correction)
};

// "auto", "every head", "none".
const char* LiftCorrectionModeName(LiftCorrectionMode mode);

struct LiftCorrectionOptions {
  LiftCorrectionMode mode = LiftCorrectionMode::kAuto;
  // kAuto takes the parallax out when the heads' actuated lifts, each over
  // its standard uncertainty, would be less likely than this for heads
  // that stay in the plane (a chi-squared test of their sum of squares).
  // On the lift bench's heads (lifts of 0-0.6 mm) the test gives p below
  // 1e-5; on flat footage (the samples and the coverage families) above
  // 0.7.
  double significance = 0.01;

  // The first bad field, named, and what it must be.
  std::optional<std::string> Problem() const;
};

// What the measured lifts say, and what was done.
struct LiftCorrectionDecision {
  LiftCorrectionMode mode = LiftCorrectionMode::kAuto;
  bool correct = false;  // the parallax is taken out of every head
  // The test: the actuated lifts that have a u (every head, every measured
  // test), the sum of their (lift / u)^2, and its probability for heads
  // that stay in the plane (NaN without lifts).
  int lifts = 0;
  double chi_squared = NAN;
  double p_value = NAN;
  // One sentence: what was decided and why.
  std::string reason;
};

// Decides from a validation scored without the correction: kAuto corrects
// when the lifts' p_value is below options.significance, and only when the
// lifts' u has the codec's term (at least min_codec_jumps jumps at I
// pictures: without it a flat head's lift looks significant, its u too
// small by the codec's error in the dots' spacing). kEveryHead and kNone
// decide as told, with the test's figures for the record.
LiftCorrectionDecision DecideLiftCorrection(
    const ValidationResult& result, int min_codec_jumps,
    const LiftCorrectionOptions& options);

// A plan's tests scored (ScoreTests), with the lift correction decided
// from that score: where it asks for the parallax to come out, it is taken
// out of `measurement` (TakeOutParallax) and the tests are scored again.
// The one place validate corrects: a measurement with no parallax in any
// frame (no camera above the plane) is left as it is, and the decision
// says so rather than that it was corrected.
struct LiftCorrectedScore {
  ValidationResult result;
  LiftCorrectionDecision decision;
};
LiftCorrectedScore ScoreTestsCorrectingLift(
    const TestPlan& plan, const ValidationOptions& scoring,
    const LiftCorrectionOptions& options, VideoMeasurement* measurement);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_VALIDATION_LIFT_CORRECTION_H_
