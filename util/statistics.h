#ifndef SOFTBENCH_UTIL_STATISTICS_H_
#define SOFTBENCH_UTIL_STATISTICS_H_

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "util/check.h"

namespace softbench {

// The q-quantile (0 <= q <= 1) of non-empty `values` by nearest rank: the
// element at position round(q (n - 1)) in sorted order (the upper median
// for an even count). Takes the values by copy and partially sorts them.
template <typename T>
T Quantile(std::vector<T> values, double q) {
  SOFTBENCH_CHECK(!values.empty() && q >= 0.0 && q <= 1.0)
      << values.size() << " values, q = " << q;
  const auto k = static_cast<size_t>(std::lround(q * (values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

template <typename T>
T Median(std::vector<T> values) {
  return Quantile(std::move(values), 0.5);
}

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_STATISTICS_H_
