#ifndef SOFTBENCH_UTIL_CHECK_H_
#define SOFTBENCH_UTIL_CHECK_H_

#include <cstdlib>
#include <iostream>
#include <sstream>

// Programmer errors (docs/error-policy.md): a broken promise between two
// pieces of our own code, never a user's bad input (that is an InputError).
// SOFTBENCH_CHECK(condition) << "context"; prints where and why, then aborts,
// in every build type: unlike assert(), Release does not compile it out, so a
// broken invariant never turns into a silently wrong number.
#define SOFTBENCH_CHECK(condition) \
  if (condition) {                 \
  } else                           \
    ::softbench::internal::CheckFailure(__FILE__, __LINE__, #condition).stream()

namespace softbench::internal {

// Collects the message of a failed SOFTBENCH_CHECK and aborts when the
// statement ends.
class CheckFailure {
 public:
  [[gnu::cold, gnu::noinline]] CheckFailure(const char* file, int line,
                                            const char* condition) {
    stream_ << "softbench: internal error: " << file << ":" << line
            << ": check failed: " << condition << ": ";
  }
  CheckFailure(const CheckFailure&) = delete;
  CheckFailure& operator=(const CheckFailure&) = delete;
  [[noreturn, gnu::cold, gnu::noinline]] ~CheckFailure() {
    std::cerr << stream_.str() << std::endl;
    std::abort();
  }
  [[gnu::cold]] std::ostream& stream() { return stream_; }

 private:
  std::ostringstream stream_;
};

}  // namespace softbench::internal

#endif  // SOFTBENCH_UTIL_CHECK_H_
