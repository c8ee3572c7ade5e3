#include "util/check.h"

#include <gtest/gtest.h>

namespace softbench {
namespace {

int Twice(int value) {
  SOFTBENCH_CHECK(value >= 0) << "value " << value << " must be >= 0";
  return 2 * value;
}

TEST(Check, PassesQuietlyWhenTheConditionHolds) { EXPECT_EQ(Twice(3), 6); }

// The test runs in every build type, Release included: a check is never
// compiled out.
TEST(CheckDeathTest, AbortsWithWhereAndWhyInEveryBuildType) {
  EXPECT_DEATH(Twice(-1),
               "internal error: .*check_test.cc:[0-9]+: check failed: value "
               ">= 0: value -1 must be >= 0");
}

TEST(CheckDeathTest, WorksAsTheOnlyStatementOfAnIf) {
  // The macro's dangling-else guard: the else below belongs to the outer if.
  bool reached_else = false;
  if (Twice(1) == 0)
    SOFTBENCH_CHECK(false) << "not reached";
  else
    reached_else = true;
  EXPECT_TRUE(reached_else);
}

}  // namespace
}  // namespace softbench
