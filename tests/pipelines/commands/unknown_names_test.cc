// Every named choice on the command line, given a name it does not know
// (empty included), answers through `main` with one line that lists the
// known names, and exit code 2 (docs/error-policy.md).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/scratch_directory.h"

namespace softbench {
namespace {

struct Case {
  std::string arguments;  // after `softbench`
  std::string expected;   // the whole message after "softbench: error: "
};

using UnknownNamesTest = ScratchDirectoryTest;

TEST_F(UnknownNamesTest, EachGetsOneLineListingTheKnownNames) {
  const std::string samples = std::string(SOFTBENCH_SOURCE_DIR) + "/samples";
  const std::string variants = "use small-angle, full-trig or variable-arm";
  const std::vector<Case> cases = {
      {"fit logs.yaml --variant ''",
       "--variant: '' is not a variant; " + variants},
      {"fit logs.yaml --variant exact",
       "--variant: 'exact' is not a variant; " + variants},
      {"predict --pressures 1,1,1 --variant ''",
       "--variant: '' is not a variant; " + variants},
      {"predict --pressures 1,1,1 --model spring",
       "--model: 'spring' is not a model; use axial-shear or "
       "pressurized-spring"},
      {"predict --pressures 1,1,1 --pressure-unit atm",
       "--pressure-unit: 'atm' is not a unit; use psi, kpa, mpa or bar"},
      {"predict --pressures 1,1,1 --mechanism ''",
       "mechanism '': no such mechanism; give 'delta', 'floating', or the "
       "path of a mechanism YAML file"},
      {"workspace --max 6 --step 3 --pressure-unit ''",
       "--pressure-unit: '' is not a unit; use psi, kpa, mpa or bar"},
      {"synth-forces --out " + Path("logs") + " --variant exact",
       "--variant: 'exact' is not a variant; " + variants},
      {"synth-forces --out " + Path("logs") + " --pressure-unit atm",
       "--pressure-unit: 'atm' is not a unit; use psi, kpa, mpa or bar"},
      {"tune " + samples + "/delta/delta.mp4 --color purple",
       "--color: 'purple' is not red, green, blue, yellow or magenta"},
      {"validate " + samples + "/delta/delta.mp4 --plan " + samples +
           "/delta/plan.yaml --out " + Path("report") + " --variant ''",
       "--variant: '' is not a variant; " + variants},
  };
  for (const Case& c : cases) {
    std::string err;
    EXPECT_EQ(RunProgram(c.arguments, &err), 2) << c.arguments << "\n" << err;
    EXPECT_EQ(err, "softbench: error: " + c.expected + "\n") << c.arguments;
  }
}

}  // namespace
}  // namespace softbench
