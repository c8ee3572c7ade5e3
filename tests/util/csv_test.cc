#include "util/csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "util/input_error.h"

namespace softbench {
namespace {

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path =
      (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path) << text;
  return path;
}

TEST(ParseDouble, AcceptsWholeNumbersOnly) {
  EXPECT_EQ(ParseDouble("6"), 6.0);
  EXPECT_EQ(ParseDouble(" -1.25e-3 "), -1.25e-3);
  EXPECT_EQ(ParseDouble("+2"), 2.0);
  EXPECT_FALSE(ParseDouble("").has_value());
  EXPECT_FALSE(ParseDouble("6psi").has_value());
  EXPECT_FALSE(ParseDouble("abc").has_value());
  EXPECT_FALSE(ParseDouble("1,5").has_value());
  EXPECT_TRUE(std::isnan(*ParseDouble("nan")));
}

TEST(CsvReader, SkipsCommentsAndBlankLinesAndCountsLines) {
  const std::string path =
      WriteTemp("softbench_csv_ok.csv", "# note\np1, p2\r\n\n1,2\n# x\n3 ,4\n");
  CsvReader reader(path);
  EXPECT_EQ(reader.header(), (std::vector<std::string>{"p1", "p2"}));
  EXPECT_EQ(reader.ColumnIndex("p2"), 1);
  EXPECT_EQ(reader.ColumnIndex("p3"), -1);
  std::vector<std::string_view> fields;
  ASSERT_TRUE(reader.ReadRow(&fields));
  EXPECT_EQ(reader.line_number(), 4);
  EXPECT_EQ(fields[1], "2");
  ASSERT_TRUE(reader.ReadRow(&fields));
  EXPECT_EQ(reader.line_number(), 6);
  EXPECT_EQ(fields[0], "3");
  EXPECT_FALSE(reader.ReadRow(&fields));
}

TEST(CsvReader, NamesFileAndLineOfARowWithTheWrongFieldCount) {
  const std::string path = WriteTemp("softbench_csv_bad.csv", "a,b\n1,2\n3\n");
  CsvReader reader(path);
  std::vector<std::string_view> fields;
  ASSERT_TRUE(reader.ReadRow(&fields));
  try {
    reader.ReadRow(&fields);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":3:"), std::string::npos)
        << e.what();
  }
}

TEST(CsvReader, RejectsMissingAndEmptyFiles) {
  EXPECT_THROW(CsvReader("/nonexistent/softbench.csv"), InputError);
  EXPECT_THROW(CsvReader(WriteTemp("softbench_csv_empty.csv", "# only\n")),
               InputError);
}

}  // namespace
}  // namespace softbench
