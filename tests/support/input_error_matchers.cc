#include "tests/support/input_error_matchers.h"

namespace softbench {

std::string InputErrorOf(const std::function<void()>& run) {
  try {
    run();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace softbench
