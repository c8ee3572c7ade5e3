#include "tests/support/coverage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "util/statistics.h"

namespace softbench {

std::string RandomDeltaTests(int count, uint32_t seed,
                             const std::function<std::string(int)>& extra) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> pressure(0.0, 6.0);
  std::string yaml;
  for (int i = 0; i < count; ++i) {
    yaml += "  - {id: t" + std::to_string(i) + ", pressures: [";
    for (int k = 0; k < 3; ++k) {
      yaml += (k > 0 ? ", " : "") +
              std::to_string(std::round(10.0 * pressure(random)) / 10.0);
    }
    yaml += "]" + extra(i) + "}\n";
  }
  return yaml;
}

TestPlan TimedDeltaPlan(int count) {
  const std::string yaml =
      "mechanism: delta\n"
      "pressure_unit: psi\n"
      "calibration: {mm_per_px: 0.1}\n"
      "tests:\n" +
      RandomDeltaTests(count, 3, [](int i) {
        return ", actuate_s: " + std::to_string(2.0 + 6.0 * i) +
               ", release_s: " + std::to_string(5.0 + 6.0 * i);
      });
  return ParseTestPlan(yaml, "plan.yaml");
}

void ExpectCoverageTargets(const std::vector<double>& errors_mm,
                           const std::vector<double>& u_mm) {
  ASSERT_EQ(errors_mm.size(), u_mm.size());
  ASSERT_FALSE(errors_mm.empty());
  int within_u = 0, within_2u = 0;
  double squares = 0.0;
  for (size_t i = 0; i < errors_mm.size(); ++i) {
    within_u += errors_mm[i] <= u_mm[i] ? 1 : 0;
    within_2u += errors_mm[i] <= 2.0 * u_mm[i] ? 1 : 0;
    squares += errors_mm[i] * errors_mm[i];
  }
  const double n = static_cast<double>(errors_mm.size());
  const double rms = std::sqrt(squares / n);
  EXPECT_GE(within_2u / n, 0.95) << "RMS error " << rms << " mm";
  EXPECT_GE(within_u / n, 0.60) << "RMS error " << rms << " mm";
  EXPECT_LE(Median(u_mm), 2.0 * rms) << "RMS error " << rms << " mm";
}

}  // namespace softbench
