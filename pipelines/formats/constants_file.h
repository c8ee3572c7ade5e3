#ifndef SOFTBENCH_PIPELINES_FORMATS_CONSTANTS_FILE_H_
#define SOFTBENCH_PIPELINES_FORMATS_CONSTANTS_FILE_H_

#include <optional>
#include <string>
#include <string_view>

#include "model/actuator_model.h"
#include "model/characterised_range.h"

namespace softbench {

// An actuator constants file (samples/constants/thesis.yaml), the product of
// characterisation and the input of every model command: the four fitted
// constants and, optionally, L0 and the variant they were fitted for.
struct ConstantsFile {
  ActuatorConstants constants;
  std::optional<std::string> variant;  // "small-angle", "full-trig", ...
  // The range the constants were fitted over (keys characterised_*; the
  // thesis's protocol when absent): predictions beyond it are marked.
  CharacterisedRange range;
};

// Parses a constants YAML document; throws InputError naming the line and
// key. `source` names the document in messages.
ConstantsFile ParseConstantsYaml(std::string_view yaml,
                                 const std::string& source);
ConstantsFile LoadConstantsFile(const std::string& path);

// The YAML text of a constants file (what ParseConstantsYaml reads), with
// `comment` (lines starting with '#') on top.
std::string ConstantsYaml(const ConstantsFile& file, std::string_view comment);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_CONSTANTS_FILE_H_
