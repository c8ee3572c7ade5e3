#include "util/statistics.h"

#include <gtest/gtest.h>

namespace softbench {
namespace {

TEST(Quantile, NearestRankOnUnsortedValues) {
  const std::vector<double> values = {5, 1, 4, 2, 3};
  EXPECT_EQ(Median(values), 3.0);
  EXPECT_EQ(Quantile(values, 0.0), 1.0);
  EXPECT_EQ(Quantile(values, 1.0), 5.0);
  EXPECT_EQ(Quantile(values, 0.3), 2.0);               // rank round(1.2) = 1
  EXPECT_EQ(Median(std::vector<int>{4, 1, 3, 2}), 3);  // upper median
}

}  // namespace
}  // namespace softbench
