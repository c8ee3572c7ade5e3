#ifndef SOFTBENCH_TESTS_SUPPORT_COVERAGE_H_
#define SOFTBENCH_TESTS_SUPPORT_COVERAGE_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"

namespace softbench {

// `count` test points of a delta plan's `tests:` list, "  - {id: tI,
// pressures: [A, B, C]EXTRA}" with pressures drawn uniformly from 0-6 psi
// to 0.1 psi (fixed `seed`), and EXTRA = `extra(I)` (", actuate_s: ...").
std::string RandomDeltaTests(
    int count, uint32_t seed,
    const std::function<std::string(int)>& extra = [](int) { return ""; });

// A delta plan (mm_per_px 0.1, no tag) of `count` such test points, one
// after another: actuated for 3 s from 2 + 6i s, then resting 3 s.
TestPlan TimedDeltaPlan(int count);

// Checks issue 26's targets for measured errors against their reported
// standard uncertainties u (both [mm], same order): at least 95 % within
// U = 2u, at least 60 % within u, and the median u at most 2x the RMS
// error (not inflated). Each miss is a test failure naming the figures.
void ExpectCoverageTargets(const std::vector<double>& errors_mm,
                           const std::vector<double>& u_mm);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_COVERAGE_H_
