#ifndef SOFTBENCH_PIPELINES_COMMANDS_MODEL_FLAGS_H_
#define SOFTBENCH_PIPELINES_COMMANDS_MODEL_FLAGS_H_

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <string>
#include <vector>

#include "model/mechanism.h"
#include "pipelines/commands/model_selection.h"

namespace softbench {

// Adds --mechanism, --model, --variant, --constants and --pressure-unit.
void AddModelSelectionOptions(CLI::App* command, ModelSelection* selection);

// Parses "a,b,c" into numbers; throws InputError naming `option` and the
// offending item.
std::vector<double> ParseNumberList(const std::string& text,
                                    const std::string& option);

// Formats head displacements "head: y = ... mm, z = ... mm; ..." for people.
std::string FormatHeadPositions(const Mechanism& mechanism,
                                const Eigen::VectorXd& displacements_mm);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_MODEL_FLAGS_H_
