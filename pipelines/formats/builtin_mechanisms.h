#ifndef SOFTBENCH_PIPELINES_FORMATS_BUILTIN_MECHANISMS_H_
#define SOFTBENCH_PIPELINES_FORMATS_BUILTIN_MECHANISMS_H_

#include <string_view>
#include <vector>

namespace softbench {

// A mechanism bundled with softbench: a file of samples/mechanisms/, named
// by its file name without ".yaml" and embedded at build time
// (builtin_mechanisms.cc.in), so the files stay the one source. A new
// built-in mechanism is one new file there (docs/architecture.md).
struct BuiltinMechanism {
  std::string_view name;  // "delta"
  std::string_view yaml;  // the file's text
};

// Every bundled mechanism, sorted by name.
const std::vector<BuiltinMechanism>& BuiltinMechanisms();

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_BUILTIN_MECHANISMS_H_
