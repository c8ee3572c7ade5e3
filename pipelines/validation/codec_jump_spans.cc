#include "pipelines/validation/codec_jump_spans.h"

#include <algorithm>

#include "util/check.h"

namespace softbench {
namespace {

// StillIntraJumps needs this many frames on each side of the I picture.
constexpr int kMinSide = 3;

// `n` of `times`, spread evenly (the middles of n equal shares).
std::vector<double> SpreadEvenly(const std::vector<double>& times, size_t n) {
  std::vector<double> picked;
  n = std::min(n, times.size());
  for (size_t i = 0; i < n; ++i) {
    picked.push_back(times[(2 * i + 1) * times.size() / (2 * n)]);
  }
  return picked;
}

}  // namespace

std::optional<std::string> CodecJumpSpanOptions::Problem() const {
  if (!(settle_s >= 0.0)) return "settle_s must be >= 0 s";
  if (frames_per_side < kMinSide) {
    return "frames_per_side must be >= " + std::to_string(kMinSide);
  }
  return std::nullopt;
}

CodecJumpSpans PlanCodecJumpSpans(const TestPlan& plan,
                                  const std::vector<TimeSpan>& window_spans,
                                  const VideoInfo& info, int min_jumps,
                                  const CodecJumpSpanOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  SOFTBENCH_CHECK(plan.HasTimes()) << "codec jump spans need the test times";
  CodecJumpSpans result;
  const int heads = static_cast<int>(plan.markers.size());
  const double dt = info.frame_interval_s;
  if (heads == 0 || plan.tests.empty() || !(dt > 0.0)) return result;
  // Key frames with a still head's frames on both sides inside a window
  // give their jumps already.
  const auto in_window = [&](double t) {
    return std::any_of(window_spans.begin(), window_spans.end(),
                       [&](const TimeSpan& span) {
                         return t - (kMinSide + 0.5) * dt >= span.start_s &&
                                t + (kMinSide - 0.5) * dt <= span.end_s;
                       });
  };
  // A jump needs kMinSide frames on each side with no other I picture (an
  // intra-only video has none).
  std::vector<double> keys_s;
  const std::vector<double>& all_s = info.key_frame_times_s;
  for (size_t k = 0; k < all_s.size(); ++k) {
    if ((k == 0 || all_s[k] - all_s[k - 1] > (kMinSide + 0.5) * dt) &&
        (k + 1 == all_s.size() ||
         all_s[k + 1] - all_s[k] > (kMinSide - 0.5) * dt)) {
      keys_s.push_back(all_s[k]);
    }
  }
  for (const double t : keys_s) {
    result.window_jumps += in_window(t) ? heads : 0;
  }
  if (result.window_jumps >= min_jumps) return result;

  // The others well clear of every pressure change, by where they fall.
  std::vector<double> changes_s;
  for (const TestPoint& test : plan.tests) {
    changes_s.push_back(*test.actuate_s);
    changes_s.push_back(*test.release_s);
  }
  const double reach_s = (options.frames_per_side + 0.5) * dt;
  std::vector<double> holds_s, rests_s;
  for (const double t : keys_s) {
    const double from_s = t - reach_s, to_s = t + reach_s;
    // The lead-in is the rest every position is taken from: left as read.
    if (in_window(t) || from_s < *plan.tests.front().actuate_s ||
        to_s > info.LastFrameS()) {
      continue;
    }
    if (std::any_of(changes_s.begin(), changes_s.end(), [&](double c) {
          return from_s < c + options.settle_s && to_s > c;
        })) {
      continue;
    }
    const bool held = std::any_of(
        plan.tests.begin(), plan.tests.end(), [&](const TestPoint& test) {
          return t > *test.actuate_s && t < *test.release_s;
        });
    (held ? holds_s : rests_s).push_back(t);
  }
  const size_t wanted = (min_jumps - result.window_jumps + heads - 1) / heads;
  const size_t rests = std::min(
      rests_s.size(),
      std::max((wanted + 1) / 2, wanted - std::min(wanted, holds_s.size())));
  std::vector<double> picked = SpreadEvenly(rests_s, rests);
  for (const double t : SpreadEvenly(holds_s, wanted - rests)) {
    picked.push_back(t);
  }
  std::sort(picked.begin(), picked.end());
  for (const double t : picked) {
    result.spans.push_back({t - reach_s, t + reach_s});
  }
  result.span_jumps = static_cast<int>(picked.size()) * heads;
  return result;
}

}  // namespace softbench
