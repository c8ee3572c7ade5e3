#include "pipelines/measurement/test_point_detection.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "util/check.h"
#include "util/statistics.h"

namespace softbench {
namespace {

// Time at which the motion crosses `level` between frames a and b (linear).
double Crossing(const std::vector<double>& t, const std::vector<double>& m,
                size_t a, size_t b, double level) {
  const double span = m[b] - m[a];
  if (span == 0.0) return t[b];
  return t[a] + (t[b] - t[a]) * std::clamp((level - m[a]) / span, 0.0, 1.0);
}

}  // namespace

std::optional<std::string> TestPointDetectionOptions::Problem() const {
  if (!(min_motion_mm > 0.0) || !(noise_factor > 0.0)) {
    return "min_motion_mm and noise_factor must be > 0";
  }
  if (!(min_gap_s >= 0.0) || !(min_hold_s >= 0.0)) {
    return "min_gap_s and min_hold_s must be >= 0";
  }
  if (!(crossing_fraction > 0.0 && crossing_fraction < 0.5)) {
    return "crossing_fraction must be in (0, 0.5)";
  }
  return std::nullopt;
}

namespace {

// The motion signal: the largest distance of any head from rest, over the
// frames where every head was measured.
void MotionSignal(const VideoMeasurement& measurement, std::vector<double>* t,
                  std::vector<double>* motion) {
  for (const FrameSample& frame : measurement.frames) {
    double largest = 0.0;
    bool complete = true;
    for (const HeadSample& head : frame.heads) {
      complete &= head.displacement_mm.allFinite();
      if (complete) largest = std::max(largest, head.displacement_mm.norm());
    }
    if (!complete) continue;
    t->push_back(frame.time_s);
    motion->push_back(largest);
  }
}

// Splits the excursion [first, last] where it comes down to a rest that is
// not the first one: a test point that slips (hysteresis) leaves the head
// off its rest, so the next test's excursion joins it. A rest is at least
// `min_rest_s` of frames below half of both holds beside it (the largest
// motion before and after it in the excursion); what is left of the
// excursion either side is appended to `out` as [first, last] frames.
void SplitAtRests(const std::vector<double>& t,
                  const std::vector<double>& motion, size_t first, size_t last,
                  double min_rest_s,
                  std::vector<std::pair<size_t, size_t>>* out) {
  std::vector<double> before(last - first + 1), after(last - first + 1);
  for (size_t i = first; i <= last; ++i) {
    before[i - first] =
        std::max(motion[i], i > first ? before[i - first - 1] : 0.0);
  }
  for (size_t i = last + 1; i-- > first;) {
    after[i - first] =
        std::max(motion[i], i < last ? after[i - first + 1] : 0.0);
  }
  const auto resting = [&](size_t i) {
    return motion[i] < 0.5 * std::min(before[i - first], after[i - first]);
  };
  size_t start = first;
  for (size_t i = first; i <= last;) {
    if (!resting(i)) {
      ++i;
      continue;
    }
    size_t end = i;
    while (end + 1 <= last && resting(end + 1)) ++end;
    if (t[end] - t[i] >= min_rest_s && i > start) {
      out->push_back({start, i - 1});
      start = end + 1;
    }
    i = end + 1;
  }
  if (start <= last) out->push_back({start, last});
}

// Excursions above the threshold, merged across short gaps and split at
// rests off the first one, as [first, last] frames; those shorter than a
// hold dropped.
std::vector<std::pair<size_t, size_t>> Excursions(
    const std::vector<double>& t, const std::vector<double>& motion,
    double threshold_mm, const TestPointDetectionOptions& options) {
  std::vector<std::pair<size_t, size_t>> runs;
  for (size_t i = 0; i < t.size(); ++i) {
    if (motion[i] <= threshold_mm) continue;
    if (!runs.empty() && t[i] - t[runs.back().second] < options.min_gap_s) {
      runs.back().second = i;
    } else {
      runs.emplace_back(i, i);
    }
  }
  std::vector<std::pair<size_t, size_t>> split;
  for (const auto& [first, last] : runs) {
    SplitAtRests(t, motion, first, last, options.min_gap_s, &split);
  }
  std::erase_if(split, [&](const std::pair<size_t, size_t>& run) {
    return t[run.second] - t[run.first] < options.min_hold_s;
  });
  return split;
}

// One excursion's test point: its hold level, and the crossings of a
// fraction f of it on the way up and down.
DetectedTestPoint TestPointOf(const std::vector<double>& t,
                              const std::vector<double>& motion, size_t first,
                              size_t last, double f) {
  // The hold's level at its end: the median over the second before the
  // motion falls below half its peak (robust to the fall's own frames,
  // which last 0.7 tau above half).
  const double peak =
      *std::max_element(motion.begin() + first, motion.begin() + last + 1);
  size_t half = last;
  while (half > first && motion[half] < 0.5 * peak) --half;
  std::vector<double> late;
  for (size_t i = first; i <= half; ++i) {
    if (t[i] >= t[half] - 1.0) late.push_back(motion[i]);
  }
  const double level = Median(late);
  DetectedTestPoint point;
  point.hold_motion_mm = level;
  // Actuation: the first crossing of f * level on the way up, searched
  // back from the run's start.
  size_t a = first;
  while (a > 0 && motion[a - 1] >= f * level) --a;
  point.actuate_s = a > 0 ? Crossing(t, motion, a - 1, a, f * level) : t[a];
  // Release: the last frame at (1 - f) of the level before the fall.
  size_t b = last;
  while (b > first && motion[b] < (1.0 - f) * level) --b;
  point.release_s = b + 1 < t.size()
                        ? Crossing(t, motion, b, b + 1, (1.0 - f) * level)
                        : t[b];
  return point;
}

std::string WrongCount(const TestPointDetection& result, int expected) {
  std::string seen;
  for (const DetectedTestPoint& p : result.points) {
    seen += fmt::format("{}{:.1f}-{:.1f} s", seen.empty() ? "" : ", ",
                        p.actuate_s, p.release_s);
  }
  return fmt::format(
      "the motion shows {} test point{} (heads more than {:.3f} mm from "
      "rest{}{}) but the plan lists {}; give the tests' actuate_s and "
      "release_s, or check the plan's test list",
      result.points.size(), result.points.size() == 1 ? "" : "s",
      result.threshold_mm, seen.empty() ? "" : ": ", seen, expected);
}

}  // namespace

TestPointDetection DetectTestPoints(const VideoMeasurement& measurement,
                                    int expected,
                                    const TestPointDetectionOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  TestPointDetection result;
  std::vector<double> t, motion;
  MotionSignal(measurement, &t, &motion);
  if (t.size() < 3) {
    result.why_not = "too few frames with every head measured";
    return result;
  }
  result.threshold_mm = std::max(options.min_motion_mm,
                                 options.noise_factor * Quantile(motion, 0.1));
  for (const auto& [first, last] :
       Excursions(t, motion, result.threshold_mm, options)) {
    result.points.push_back(
        TestPointOf(t, motion, first, last, options.crossing_fraction));
  }
  if (static_cast<int>(result.points.size()) != expected) {
    result.why_not = WrongCount(result, expected);
    return result;
  }
  result.found = true;
  return result;
}

}  // namespace softbench
