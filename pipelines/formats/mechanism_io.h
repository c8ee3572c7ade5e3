#ifndef SOFTBENCH_PIPELINES_FORMATS_MECHANISM_IO_H_
#define SOFTBENCH_PIPELINES_FORMATS_MECHANISM_IO_H_

#include <string>
#include <string_view>
#include <vector>

#include "model/mechanism.h"

namespace softbench {

// Parses a mechanism YAML document (format: docs/file-formats.md, "Mechanism",
// and samples/mechanisms/). `source` names the document in error messages.
// Throws InputError with the line and the field on any problem, including a
// network that fails Mechanism::Problem().
Mechanism ParseMechanismYaml(std::string_view yaml, const std::string& source);

// The name of a bundled mechanism ("delta", "floating": every file of
// samples/mechanisms/, compiled in) gives that file; anything else is read as
// a file path.
Mechanism LoadMechanism(const std::string& name_or_path);

// Names accepted by LoadMechanism without a file.
std::vector<std::string> BuiltinMechanismNames();

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_MECHANISM_IO_H_
