// softbench: bench videos of soft pneumatic mechanisms to model-validation
// reports. The commands come from the command table; this file parses the
// command line, sets up logging and is the one place user errors are caught
// (docs/error-policy.md).
#include <glog/logging.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <opencv2/core/utils/logger.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pipelines/commands/command_table.h"
#include "pipelines/commands/stderr_progress.h"
#include "util/input_error.h"
#include "util/memory_policy.h"
#include "util/progress.h"
#include "util/version.h"

namespace {

// Exit codes: 0 success, 1 internal failure, 2 bad input (a file or the
// command line), 3 unreachable target (inverse) or tests unlike their plan
// entries (validate), 4 an incomplete installation.
constexpr int kExitInternal = 1;
constexpr int kExitInputError = 2;
constexpr int kExitInstallation = 4;

// A malformed command line as one line, like every other bad input, naming
// the help of the command it was for.
std::string CommandLineError(const CLI::App* app, const CLI::Error& error) {
  std::string help = "softbench --help";
  for (const CLI::App* subcommand : app->get_subcommands()) {
    help = "softbench " + subcommand->get_name() + " --help";
  }
  // No command parsed although a word was given: the word is not a command
  // (CLI11 would only say that one is required).
  const std::vector<std::string> extras = app->remaining();
  if (app->get_subcommands().empty() && !extras.empty()) {
    std::string names;
    for (const softbench::Command& command : softbench::Commands()) {
      names += (names.empty() ? "" : ", ") + std::string(command.name);
    }
    return "softbench: error: '" + extras.front() +
           "' is not a command; use one of " + names + " (see '" + help +
           "')\n";
  }
  return "softbench: error: " + std::string(error.what()) + "; see '" + help +
         "'\n";
}

// Every option's value that reads as a number must be a finite one: CLI11
// reads "nan", "inf" and "1e999" into a double as readily as "6", and no
// flag of softbench means anything with them. Lists ("6,6,0") and words
// pass through to the command's own checks.
const CLI::Validator kFiniteNumber(
    [](std::string& value) -> std::string {
      const char* begin = value.c_str();
      char* end = nullptr;
      const double number = std::strtod(begin, &end);
      if (end == begin || *end != '\0' || std::isfinite(number)) return "";
      return "'" + value + "' is not a finite number";
    },
    "", "finite number");

}  // namespace

// An exception escaping the set-up below, before the one catch, is a bug in
// the command table: terminating on it is right.
int main(int argc, char** argv) {  // NOLINT(bugprone-exception-escape)
  softbench::KeepFreedMemory();
  CLI::App app{
      "softbench: soft pneumatic actuator mechanisms, from model to bench "
      "video"};
  app.require_subcommand(1);
  app.failure_message(CommandLineError);
  // Global options work anywhere on the line: an option a subcommand does
  // not know falls through to here (`softbench validate ... -q`).
  app.fallthrough();
  app.set_version_flag(
      "--version", std::string("softbench ") + softbench::SoftbenchVersion());
  softbench::GlobalFlags global;
  app.add_flag("--quiet,-q", global.quiet,
               "print errors only (no progress, no warnings)");
  std::vector<std::pair<CLI::App*, softbench::CommandRun>> runs;
  for (const softbench::Command& command : softbench::Commands()) {
    CLI::App* subcommand = app.add_subcommand(std::string(command.name),
                                              std::string(command.help));
    runs.emplace_back(subcommand, command.add_flags(subcommand));
    for (CLI::Option* option : subcommand->get_options()) {
      if (option->nonpositional() && option->get_expected_min() > 0) {
        option->check(kFiniteNumber);
      }
    }
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every malformed line is bad input.
    return app.exit(e) == 0 ? 0 : kExitInputError;
  }
  // Third-party libraries print nothing of their own: Ceres (through glog)
  // and OpenCV report their failures to softbench's code, which turns them
  // into its own messages (a solver's summary, an image that did not load),
  // so their lines would only repeat them in another voice or, as glog's
  // "Logging before InitGoogleLogging()", confuse. FFmpeg is silenced where
  // vision/ opens it, and encoder presets are checked before x264 sees them.
  FLAGS_minloglevel = google::GLOG_FATAL;
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  auto logger = spdlog::stderr_color_mt("softbench");
  logger->set_pattern("softbench: %l: %v");
  logger->set_level(global.quiet ? spdlog::level::err : spdlog::level::info);
  spdlog::set_default_logger(logger);
  // The libraries report long work; the command line draws it on stderr.
  static softbench::StderrProgress progress;
  softbench::SetProgressSink(&progress);

  try {
    for (const auto& [subcommand, run] : runs) {
      if (subcommand->parsed()) return run(global, std::cout);
    }
  } catch (const softbench::InputError& e) {
    spdlog::error("{}", e.what());
    return kExitInputError;
  } catch (const softbench::InstallationError& e) {
    spdlog::error("{}", e.what());
    return kExitInstallation;
  } catch (const std::exception& e) {
    spdlog::critical("internal error: {}", e.what());
    return kExitInternal;
  }
  return kExitInternal;
}
