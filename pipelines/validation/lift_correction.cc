#include "pipelines/validation/lift_correction.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>

#include "util/check.h"

namespace softbench {

const char* LiftCorrectionModeName(LiftCorrectionMode mode) {
  switch (mode) {
    case LiftCorrectionMode::kAuto:
      return "auto";
    case LiftCorrectionMode::kEveryHead:
      return "every head";
    case LiftCorrectionMode::kNone:
      return "none";
  }
  SOFTBENCH_CHECK(false) << "unknown lift correction mode";
  return "";
}

std::optional<std::string> LiftCorrectionOptions::Problem() const {
  if (!(significance > 0.0 && significance < 1.0)) {
    return "significance: must be in (0, 1)";
  }
  return std::nullopt;
}

LiftCorrectionDecision DecideLiftCorrection(
    const ValidationResult& result, int min_codec_jumps,
    const LiftCorrectionOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  LiftCorrectionDecision decision;
  decision.mode = options.mode;
  double sum = 0.0;
  for (const TestScore& t : result.tests) {
    if (!t.measured) continue;
    for (const HeadScore& h : t.heads) {
      if (!(std::isfinite(h.lift_mm) && h.u_lift_mm > 0.0)) continue;
      sum += (h.lift_mm / h.u_lift_mm) * (h.lift_mm / h.u_lift_mm);
      ++decision.lifts;
    }
  }
  if (decision.lifts > 0) {
    decision.chi_squared = sum;
    // The lifts of heads that stay in the plane, each over its u, are
    // standard normal: their sum of squares is chi-squared with one degree
    // of freedom per lift.
    decision.p_value = boost::math::cdf(boost::math::complement(
        boost::math::chi_squared_distribution<double>(decision.lifts), sum));
  }
  const std::string test =
      decision.lifts > 0
          ? fmt::format(
                "the heads' {} actuated lifts over their u give "
                "chi-squared {:.1f} (p = {:.2g} for heads that stay "
                "in the plane)",
                decision.lifts, decision.chi_squared, decision.p_value)
          : std::string("no test's lift was measured");
  switch (options.mode) {
    case LiftCorrectionMode::kEveryHead:
      decision.correct = true;
      decision.reason = "taken out of every head (--lift-correction); " + test;
      return decision;
    case LiftCorrectionMode::kNone:
      decision.reason =
          "left in (--no-lift-correction), and counted in each "
          "displacement's uncertainty; " +
          test;
      return decision;
    case LiftCorrectionMode::kAuto:
      break;
  }
  if (decision.lifts == 0) {
    decision.reason = "nothing to take out: " + test;
  } else if (result.codec_jumps < min_codec_jumps) {
    decision.reason = fmt::format(
        "left in, and counted in each displacement's uncertainty: the "
        "lifts' u lacks the codec's term ({} jumps at I pictures, fewer "
        "than {}), so the test cannot tell a lift from the codec's error: "
        "{}; --lift-correction takes it out",
        result.codec_jumps, min_codec_jumps, test);
  } else if (decision.p_value < options.significance) {
    decision.correct = true;
    decision.reason = fmt::format(
        "taken out: the heads leave the plane, since {}, below {}; "
        "--no-lift-correction leaves it in",
        test, options.significance);
  } else {
    decision.reason = fmt::format(
        "left in, and counted in each displacement's uncertainty: the heads "
        "stay in the plane as far as their lifts show, since {}, not below "
        "{}; --lift-correction takes it out",
        test, options.significance);
  }
  return decision;
}

LiftCorrectedScore ScoreTestsCorrectingLift(
    const TestPlan& plan, const ValidationOptions& scoring,
    const LiftCorrectionOptions& options, VideoMeasurement* measurement) {
  SOFTBENCH_CHECK(!measurement->lift_corrected)
      << "validate's positions are corrected here only";
  LiftCorrectedScore score;
  score.result = ScoreTests(plan, *measurement, scoring);
  score.decision =
      DecideLiftCorrection(score.result, scoring.min_codec_jumps, options);
  if (!score.decision.correct) return score;
  const bool has_parallax =
      std::ranges::any_of(measurement->frames, [](const FrameSample& f) {
        return std::ranges::any_of(f.heads, [](const HeadSample& s) {
          return s.parallax_mm.allFinite();
        });
      });
  if (!has_parallax) {
    score.decision.correct = false;
    score.decision.reason =
        "nothing taken out: no head's lift was measured in any frame (that "
        "needs the camera's place above the plane and a head's dots "
        "complete)";
    return score;
  }
  TakeOutParallax(measurement);
  score.result = ScoreTests(plan, *measurement, scoring);
  return score;
}

}  // namespace softbench
