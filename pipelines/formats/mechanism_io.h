#ifndef SOFTBENCH_PIPELINES_FORMATS_MECHANISM_IO_H_
#define SOFTBENCH_PIPELINES_FORMATS_MECHANISM_IO_H_

#include <string>
#include <string_view>
#include <vector>

#include "model/mechanism.h"

namespace softbench {

// Parses a mechanism YAML document (format: docs/mechanism-format.md and
// samples/mechanisms/). `source` names the document in error messages. Throws
// InputError with the line and the field on any problem, including a network
// that fails Mechanism::Problem().
Mechanism ParseMechanismYaml(std::string_view yaml, const std::string& source);

// "delta" and "floating" name the bundled mechanism files (compiled into the
// program from samples/mechanisms/); anything else is read as a file path.
Mechanism LoadMechanism(const std::string& name_or_path);

// Names accepted by LoadMechanism without a file.
std::vector<std::string> BuiltinMechanismNames();

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_MECHANISM_IO_H_
