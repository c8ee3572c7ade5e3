#ifndef SOFTBENCH_UTIL_VERSION_H_
#define SOFTBENCH_UTIL_VERSION_H_

namespace softbench {

// The project's version (CMakeLists.txt's project()), as `--version` prints
// it and every report and printed target records it.
const char* SoftbenchVersion();

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_VERSION_H_
