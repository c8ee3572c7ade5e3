#ifndef SOFTBENCH_PIPELINES_FORMATS_BUILTIN_MECHANISMS_H_
#define SOFTBENCH_PIPELINES_FORMATS_BUILTIN_MECHANISMS_H_

#include <string_view>

namespace softbench {

// The text of samples/mechanisms/delta.yaml and floating.yaml, embedded at
// build time (builtin_mechanisms.cc.in) so the files stay the one source.
extern const std::string_view kDeltaMechanismYaml;
extern const std::string_view kFloatingMechanismYaml;

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_BUILTIN_MECHANISMS_H_
