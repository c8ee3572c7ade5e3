// One command line for every command (README, "Commands"): global options
// anywhere, inputs positional, outputs --out and checked before any work,
// and README's command descriptions tested against each command's --help.
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "pipelines/commands/command_table.h"
#include "tests/support/scratch_directory.h"

namespace softbench {
namespace {

using CommandLineTest = ScratchDirectoryTest;

// The --options a text mentions.
std::set<std::string> OptionsIn(const std::string& text) {
  std::set<std::string> options;
  for (size_t at = text.find("--"); at != std::string::npos;
       at = text.find("--", at + 2)) {
    size_t end = at + 2;
    if (end >= text.size() || !std::islower(text[end])) continue;
    while (end < text.size() && (std::islower(text[end]) ||
                                 std::isdigit(text[end]) || text[end] == '-')) {
      ++end;
    }
    options.insert(text.substr(at, end - at));
  }
  return options;
}

// README's usage lines of `command`: each "softbench COMMAND ..." line with
// the indented lines that continue it.
std::vector<std::string> UsagesIn(const std::string& readme,
                                  const std::string& command) {
  std::vector<std::string> usages;
  const std::string start = "softbench " + command + " ";
  for (size_t at = readme.find(start); at != std::string::npos;
       at = readme.find(start, at + 1)) {
    size_t end = readme.find('\n', at);
    while (end != std::string::npos && readme.compare(end + 1, 2, "  ") == 0) {
      end = readme.find('\n', end + 1);
    }
    usages.push_back(readme.substr(at, end - at));
  }
  return usages;
}

TEST_F(CommandLineTest, GlobalOptionsWorkAnywhereOnTheLine) {
  std::string err, out;
  EXPECT_EQ(RunProgram("predict --pressures 6,6,0 --pressure-unit psi -q", &err,
                       &out),
            0)
      << err;
  EXPECT_NE(out.find("y = -1.1254 mm"), std::string::npos) << out;
  EXPECT_EQ(RunProgram("-q predict --pressures 6,6,0 --pressure-unit psi", &err,
                       &out),
            0)
      << err;
  EXPECT_EQ(RunProgram("--version", &err, &out), 0);
  EXPECT_EQ(out.rfind("softbench ", 0), 0u) << out;
}

TEST_F(CommandLineTest, EveryCommandWritesWithOutAndReadmeMatchesItsHelp) {
  std::ifstream stream(std::string(SOFTBENCH_SOURCE_DIR) + "/README.md");
  std::stringstream readme_stream;
  readme_stream << stream.rdbuf();
  const std::string readme = readme_stream.str();
  for (const Command& command : Commands()) {
    const std::string name(command.name);
    std::string err, help;
    ASSERT_EQ(RunProgram(name + " --help", &err, &help), 0) << name;
    const std::set<std::string> options = OptionsIn(help);
    for (const std::string& option : options) {
      if (option == "--help") continue;
      EXPECT_NE(option.find("--output"), 0u)
          << name << " writes with " << option << " instead of --out";
      EXPECT_NE(readme.find(option), std::string::npos)
          << "README does not mention " << name << "'s " << option;
    }
    // Every option README's usage lines give the command exists.
    const std::vector<std::string> usages = UsagesIn(readme, name);
    for (const std::string& usage : usages) {
      for (const std::string& option : OptionsIn(usage)) {
        if (option == "--quiet" || option == "--version") continue;
        EXPECT_TRUE(options.count(option))
            << "README gives `softbench " << name << " " << option
            << "` but --help does not list it";
      }
    }
    EXPECT_FALSE(usages.empty()) << "README shows no usage of " << name;
  }
}

// A malformed command line is bad input like any other: one line, exit 2,
// naming the help of the command it was for.
TEST_F(CommandLineTest, AMalformedLineIsOneLineOfBadInput) {
  const struct {
    std::string arguments, expected;
  } cases[] = {
      {"calibrate-camera " + dir().string() + " --out " + Path("c.yaml"),
       "softbench: error: --square-mm is required; see 'softbench "
       "calibrate-camera --help'"},
      {"predict --mechanism delta --pressures 6,6,0 --pressure-unit psi "
       "--colour red",
       "softbench: error: The following argument was not expected: "
       "--colour; see 'softbench predict --help'"},
      {"tune clip.mp4 --at soon",
       "softbench: error: Could not convert: --at = soon; see 'softbench "
       "tune --help'"},
      {"",
       "softbench: error: A subcommand is required; see 'softbench "
       "--help'"},
      {"-q valdiate clip.mp4",
       "softbench: error: 'valdiate' is not a command; use one of predict, "},
  };
  for (const auto& c : cases) {
    std::string err;
    EXPECT_EQ(RunProgram(c.arguments, &err), 2) << c.arguments << "\n" << err;
    EXPECT_NE(err.find(c.expected), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  }
  std::string out;
  EXPECT_EQ(RunProgram("--version", nullptr, &out), 0);
  EXPECT_EQ(RunProgram("fit --help", nullptr, &out), 0);
}

TEST_F(CommandLineTest, AnUnwritableOutputIsFoundBeforeAnyWork) {
  const std::string samples = std::string(SOFTBENCH_SOURCE_DIR) + "/samples";
  const struct {
    std::string arguments, expected;
  } cases[] = {
      {"validate " + samples + "/delta/delta.mp4 --plan " + samples +
           "/delta/plan.yaml --out /nonexistent/report",
       "--out: /nonexistent/report: folder '/nonexistent' does not exist"},
      {"track " + samples + "/delta/delta.mp4 --plan " + samples +
           "/delta/plan.yaml --out " + dir().string(),
       " is a folder; give a file name inside it"},
      {"render --plan " + samples + "/delta/plan.yaml --out " + Path("v.mp4") +
           " --truth /proc/truth.csv",
       "--truth: /proc/truth.csv: folder '/proc' is not writable"},
      {"synth-forces --out " + Write("file", "x"),
       " exists and is not a folder"},
      {"render --plan " + samples + "/delta/plan.yaml --out " + Path("v.txt") +
           " --truth " + Path("truth.csv"),
       "v.txt: a video is written as .mp4, .mov or .m4v; name it so"},
  };
  for (const auto& c : cases) {
    std::string err;
    EXPECT_EQ(RunProgram(c.arguments, &err), 2) << c.arguments << "\n" << err;
    EXPECT_NE(err.find(c.expected), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  }
  EXPECT_FALSE(std::filesystem::exists(Path("v.mp4")));
}

// An output that would overwrite an input (by another name too) or another
// output, or a report folder that holds an input, is refused before any
// work, and the input stays as it was.
TEST_F(CommandLineTest, AnOutputNeverOverwritesAnInput) {
  const std::string samples = std::string(SOFTBENCH_SOURCE_DIR) + "/samples";
  const std::string csv = Write("p.csv", "p1_psi,p2_psi,p3_psi\n6,6,0\n");
  std::filesystem::create_directories(Path("bench"));
  const std::string plan = Path("bench/run.plan.yaml");
  std::filesystem::copy_file(samples + "/delta/rendered.plan.yaml", plan);
  const std::string logs = Path("logs");
  std::string err;
  ASSERT_EQ(
      RunProgram("synth-forces --noise-only --rate 20 --out " + logs, &err), 0)
      << err;
  const struct {
    std::string arguments, expected;
  } cases[] = {
      {"predict " + csv + " --out " + Path("bench/../p.csv"),
       "--out: " + Path("bench/../p.csv") + " is also the pressures CSV (" +
           csv + "); write to another file"},
      {"track " + samples + "/delta/delta.mp4 --plan " + plan + " --out " +
           plan,
       "--out: " + plan + " is also --plan"},
      {"render --plan " + plan + " --out " + Path("v.mp4") + " --truth " +
           Path("v.mp4"),
       "--truth: " + Path("v.mp4") + " is also --out"},
      {"render --plan " + plan + " --out " + Path("bench/run.mp4") +
           " --truth " + Path("t.csv"),
       "--plan-out (by default VIDEO.plan.yaml): " + plan + " is also --plan"},
      {"validate " + samples + "/delta/delta.mp4 --plan " + plan + " --out " +
           Path("bench"),
       "--out: " + Path("bench") + " is replaced whole, and it holds --plan (" +
           plan + "), which would be lost"},
      {"fit " + logs + "/manifest.yaml --out " + Path("c.yaml") + " --report " +
           logs,
       "--report: " + logs + " is replaced whole, and it holds the force logs"},
  };
  const std::string before = Read(plan);
  for (const auto& c : cases) {
    EXPECT_EQ(RunProgram(c.arguments, &err), 2) << c.arguments << "\n" << err;
    EXPECT_NE(err.find(c.expected), std::string::npos) << err;
  }
  EXPECT_EQ(Read(plan), before);
  EXPECT_TRUE(std::filesystem::exists(logs + "/manifest.yaml"));
  EXPECT_FALSE(std::filesystem::exists(Path("v.mp4")));
}

}  // namespace
}  // namespace softbench
