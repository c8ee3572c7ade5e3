#include "pipelines/validation/plan_consistency.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "model/units.h"

namespace softbench {
namespace {

// `count` plan entries with distinct pressures and predictions 0.3-1.5 mm
// long in random directions (one head), measured exactly.
std::vector<TestScore> Entries(int count, std::mt19937* random) {
  std::uniform_real_distribution<double> length(0.3, 1.5), angle(-3.14, 3.14);
  std::vector<TestScore> tests(count);
  for (int i = 0; i < count; ++i) {
    TestScore& t = tests[i];
    t.id = "t" + std::to_string(i + 1);
    t.pressures = Eigen::Vector3d(i, 1, 0);
    t.measured = true;
    t.status = "ok";
    const double a = angle(*random);
    t.heads.resize(1);
    t.heads[0].model_mm =
        length(*random) * Eigen::Vector2d(std::cos(a), std::sin(a));
    t.heads[0].measured_mm = t.heads[0].model_mm;
  }
  return tests;
}

std::vector<std::string> Mismatched(const std::vector<TestScore>& tests) {
  std::vector<std::string> ids;
  for (const TestScore& t : tests) {
    if (!t.matches_plan) {
      EXPECT_EQ(t.status, "mismatch");
      EXPECT_FALSE(t.scored());
      ids.push_back(t.id);
    }
  }
  return ids;
}

TEST(PlanConsistency, NeverFlagsModelErrorsUpToThreeTenthsOfAMillimetre) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> error(-0.21, 0.21);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<TestScore> tests = Entries(14, &random);
    for (TestScore& t : tests) {
      t.heads[0].measured_mm += Eigen::Vector2d(error(random), error(random));
    }
    EXPECT_TRUE(CheckPlanConsistency(ValidationOptions(), &tests).empty());
    EXPECT_TRUE(Mismatched(tests).empty()) << "trial " << trial;
  }
}

TEST(PlanConsistency, NamesTwoSwappedTestsAndTheEntriesTheyFit) {
  std::mt19937 random(12);
  std::vector<TestScore> tests = Entries(8, &random);
  // The bench ran t3 and t6 in each other's place.
  std::swap(tests[2].heads[0].measured_mm, tests[5].heads[0].measured_mm);
  const double gap =
      (tests[2].heads[0].model_mm - tests[5].heads[0].model_mm).norm();
  ASSERT_GT(gap, 0.4) << "pick a seed whose swapped entries differ";
  const std::vector<std::string> warnings =
      CheckPlanConsistency(ValidationOptions(), &tests);
  EXPECT_EQ(Mismatched(tests), (std::vector<std::string>{"t3", "t6"}));
  EXPECT_NE(
      tests[2].reason.find("within 0.000 mm of the prediction for test t6"),
      std::string::npos)
      << tests[2].reason;
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_NE(warnings.back().find("2 of 8 tests do not move as their plan "
                                 "entries predict (t3, t6)"),
            std::string::npos)
      << warnings.back();
}

TEST(PlanConsistency, FlagsEveryTestAfterOneTheBenchSkipped) {
  std::mt19937 random(13);
  std::vector<TestScore> tests = Entries(10, &random);
  // The bench skipped t4: each later test shows the next entry's motion.
  for (int i = 3; i < 9; ++i) {
    tests[i].heads[0].measured_mm = tests[i + 1].heads[0].model_mm;
  }
  tests[9].measured = false;  // one movement short: the last is not measured
  CheckPlanConsistency(ValidationOptions(), &tests);
  const std::vector<std::string> flagged = Mismatched(tests);
  // Entries whose neighbour happens to predict nearly the same motion may
  // pass; the rest must not.
  int separable = 0;
  for (int i = 3; i < 9; ++i) {
    const double gap =
        (tests[i].heads[0].model_mm - tests[i + 1].heads[0].model_mm).norm();
    if (gap > 0.5) {
      ++separable;
      EXPECT_NE(std::find(flagged.begin(), flagged.end(), tests[i].id),
                flagged.end())
          << tests[i].id << " moved like the next entry (" << gap
          << " mm from its own) but was scored";
    }
  }
  EXPECT_GE(separable, 3);
  // t3 came before the skip: it fits, and is flagged only when most tests
  // do not (then nothing is scored).
  EXPECT_TRUE(tests[2].scored() ||
              tests[2].reason.find("most tests") != std::string::npos)
      << tests[2].reason;
}

TEST(PlanConsistency, FlagsAHeadThatStayedAtRestWhenItShouldHaveMoved) {
  std::mt19937 random(14);
  std::vector<TestScore> tests = Entries(4, &random);
  tests[1].heads[0].model_mm = Eigen::Vector2d(0.0, 1.3);
  tests[1].heads[0].measured_mm = Eigen::Vector2d(0.01, -0.01);  // times off
  CheckPlanConsistency(ValidationOptions(), &tests);
  EXPECT_EQ(Mismatched(tests), (std::vector<std::string>{"t2"}));
  EXPECT_NE(tests[1].reason.find("its motion is 1.3"), std::string::npos)
      << tests[1].reason;
}

TEST(PlanConsistency, ScoresNoTestWhenMostDoNotFitTheirEntries) {
  std::mt19937 random(16);
  std::vector<TestScore> tests = Entries(7, &random);
  // Times shifted by a hold: each window sees the motion read backwards.
  for (TestScore& t : tests) t.heads[0].measured_mm = -t.heads[0].model_mm;
  // The smallest motion reversed stays within the thresholds by itself.
  tests[6].heads[0].model_mm = Eigen::Vector2d(0.1, 0.0);
  tests[6].heads[0].measured_mm = Eigen::Vector2d(-0.1, 0.0);
  const std::vector<std::string> warnings =
      CheckPlanConsistency(ValidationOptions(), &tests);
  EXPECT_EQ(Mismatched(tests).size(), 7u);
  EXPECT_NE(tests[6].reason.find("most tests do not move"), std::string::npos)
      << tests[6].reason;
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings.back().find("the plan does not fit the video: 6 of 7"),
            std::string::npos)
      << warnings.back();
}

TEST(PlanConsistency, ScoresTheFittingMajorityWhenAFewDoNotFit) {
  std::mt19937 random(17);
  std::vector<TestScore> tests = Entries(7, &random);
  for (int i = 0; i < 3; ++i) {
    tests[i].heads[0].measured_mm = -tests[i].heads[0].model_mm;
  }
  tests[0].heads[0].model_mm = Eigen::Vector2d(1.0, 0.0);
  tests[0].heads[0].measured_mm = Eigen::Vector2d(-1.0, 0.0);
  CheckPlanConsistency(ValidationOptions(), &tests);
  const std::vector<std::string> flagged = Mismatched(tests);
  EXPECT_LE(flagged.size(), 3u);
  EXPECT_EQ(flagged.front(), "t1");
  for (int i = 3; i < 7; ++i) EXPECT_TRUE(tests[i].scored()) << tests[i].id;
}

TEST(PlanConsistency, RepeatsWithTheSamePressuresAreNotOtherEntries) {
  std::mt19937 random(15);
  std::vector<TestScore> tests = Entries(4, &random);
  tests[3].pressures = tests[0].pressures;  // t4 repeats t1
  tests[3].heads[0].model_mm = tests[0].heads[0].model_mm;
  tests[3].heads[0].measured_mm = tests[0].heads[0].model_mm;
  CheckPlanConsistency(ValidationOptions(), &tests);
  EXPECT_TRUE(Mismatched(tests).empty());
}

TEST(PlanConsistency, NeverNamesAnEntryWithoutAPredictionAsTheMatch) {
  std::mt19937 random(18);
  std::vector<TestScore> tests = Entries(6, &random);
  tests[2].predicted = false;  // the model found no equilibrium there
  tests[2].heads[0].model_mm.setConstant(NAN);
  tests[0].heads[0].measured_mm = Eigen::Vector2d(5.0, 5.0);
  CheckPlanConsistency(ValidationOptions(), &tests);
  ASSERT_FALSE(tests[0].matches_plan);
  EXPECT_EQ(tests[0].reason.find("test t3"), std::string::npos)
      << tests[0].reason;
}

// One head under three actuators, saturating (no unit's prediction is a
// plain rescaling of another's) [mm from MPa].
Eigen::VectorXd Bellows(const Eigen::VectorXd& mpa) {
  return 2.0 * Eigen::Vector2d(std::tanh(8.0 * (mpa[0] - mpa[1])),
                               std::tanh(8.0 * mpa[2]));
}

// `count` tests set in psi on the bench, measured as Bellows moves, their
// entries predicted with the pressures read in `plan_mpa_per_unit`.
std::vector<TestScore> BenchInPsi(int count, double plan_mpa_per_unit,
                                  std::mt19937* random) {
  std::uniform_real_distribution<double> psi(5.0, 25.0), noise(-0.02, 0.02);
  std::vector<TestScore> tests(count);
  for (int i = 0; i < count; ++i) {
    TestScore& t = tests[i];
    t.id = "t" + std::to_string(i + 1);
    t.pressures =
        Eigen::Vector3d(psi(*random), 0.2 * psi(*random), psi(*random));
    t.measured = true;
    t.status = "ok";
    t.heads.resize(1);
    t.heads[0].model_mm = Bellows(t.pressures * plan_mpa_per_unit);
    t.heads[0].measured_mm = Bellows(t.pressures * kMpaPerPsi) +
                             Eigen::Vector2d(noise(*random), noise(*random));
  }
  return tests;
}

TEST(PressureUnitThatFits, NamesPsiWhenThePlanSaysKpaForABenchInPsi) {
  std::mt19937 random(21);
  std::vector<TestScore> tests = BenchInPsi(10, kMpaPerKpa, &random);
  CheckPlanConsistency(ValidationOptions(), &tests);
  ASSERT_GT(Mismatched(tests).size(), 5u);
  const std::optional<std::string> hint =
      PressureUnitThatFits(ValidationOptions(), tests, "kPa", Bellows);
  ASSERT_TRUE(hint.has_value());
  EXPECT_NE(hint->find("read in psi instead of the plan's kPa, 10 of the 10 "
                       "measured tests that moved over 0.5 mm"),
            std::string::npos)
      << *hint;
  EXPECT_NE(hint->find("set pressure_unit: psi"), std::string::npos) << *hint;
}

TEST(PressureUnitThatFits, SaysNothingWhenThePlanFits) {
  std::mt19937 random(22);
  std::vector<TestScore> tests = BenchInPsi(10, kMpaPerPsi, &random);
  EXPECT_TRUE(CheckPlanConsistency(ValidationOptions(), &tests).empty());
  EXPECT_FALSE(
      PressureUnitThatFits(ValidationOptions(), tests, "psi", Bellows));
}

TEST(PressureUnitThatFits, SaysNothingWhenNoUnitExplainsTheMotion) {
  std::mt19937 random(23);
  std::vector<TestScore> tests = BenchInPsi(10, kMpaPerKpa, &random);
  for (TestScore& t : tests) t.heads[0].measured_mm *= -1.0;  // backwards
  CheckPlanConsistency(ValidationOptions(), &tests);
  ASSERT_GT(Mismatched(tests).size(), 5u);
  EXPECT_FALSE(
      PressureUnitThatFits(ValidationOptions(), tests, "kpa", Bellows));
}

TEST(PressureUnitThatFits, SaysNothingWhenTheHeadsStayedStill) {
  // The plan's unit is right, but the windows missed every actuation: no
  // unit that predicts little motion may be named for it.
  std::mt19937 random(24);
  std::vector<TestScore> tests = BenchInPsi(10, kMpaPerPsi, &random);
  for (TestScore& t : tests) t.heads[0].measured_mm.setZero();
  CheckPlanConsistency(ValidationOptions(), &tests);
  ASSERT_GT(Mismatched(tests).size(), 5u);
  EXPECT_FALSE(
      PressureUnitThatFits(ValidationOptions(), tests, "psi", Bellows));
}

}  // namespace
}  // namespace softbench
