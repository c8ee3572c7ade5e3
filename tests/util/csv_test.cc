#include "util/csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "util/input_error.h"

namespace softbench {
namespace {

std::string WriteTemp(const std::string& name, const std::string& text) {
  std::string path = (TestScratch().dir() / name).string();
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
  double value = 0.0;
  EXPECT_TRUE(ParseDouble(" 0.000175", &value));
  EXPECT_EQ(value, 0.000175);
  EXPECT_FALSE(ParseDouble("0.5x", &value));
}

// The splitter finds separators 16 bytes at a time and the rest one search at
// a time; lines of every length, with separators at every place in and
// across those blocks (both ends, doubled, padded with blanks), must split as
// the plain definition says: text between separators, trimmed.
TEST(SplitCsvLine, AgreesWithThePlainDefinitionOnRandomLines) {
  std::mt19937 random(7);
  const std::string alphabet = ",,, \t0123456789.-e";
  std::vector<std::string_view> fields;
  for (int trial = 0; trial < 4000; ++trial) {
    std::string line(random() % 70, ' ');
    for (char& c : line) c = alphabet[random() % alphabet.size()];
    std::vector<std::string> expected(1);
    for (char c : line) {
      if (c == ',') {
        expected.emplace_back();
      } else {
        expected.back() += c;
      }
    }
    for (std::string& field : expected) {
      const size_t begin = field.find_first_not_of(" \t");
      field =
          begin == std::string::npos
              ? ""
              : field.substr(begin, field.find_last_not_of(" \t") - begin + 1);
    }
    SplitCsvLine(line, &fields);
    ASSERT_EQ(std::vector<std::string>(fields.begin(), fields.end()), expected)
        << "line '" << line << "'";
  }
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
  const std::string message = InputErrorOf([&] { reader.ReadRow(&fields); });
  EXPECT_NE(message.find(path + ":3:"), std::string::npos) << message;
}

TEST(CsvReader, RejectsMissingAndEmptyFiles) {
  EXPECT_THROW(CsvReader("/nonexistent/softbench.csv"), InputError);
  EXPECT_THROW(CsvReader(WriteTemp("softbench_csv_empty.csv", "# only\n")),
               InputError);
}

// The error message of reading every row of `text`, or "" if none.
std::string ReadAllError(const std::string& name, const std::string& text,
                         DecimalMark decimal_mark = DecimalMark::kPoint) {
  return InputErrorOf([&] {
    CsvReader reader(WriteTemp(name, text), decimal_mark);
    std::vector<std::string_view> fields;
    while (reader.ReadRow(&fields)) {
    }
  });
}

// Rows across the buffer's refills, a row longer than the first buffer
// (it grows), and a line longer than any CSV row (refused, not read on).
TEST(CsvReader, ReadsRowsAcrossRefillsAndRefusesEndlessLines) {
  std::string text = "id,value\n";
  const int rows = 200000;  // about 2.4 MB: several 1 MiB refills
  for (int i = 0; i < rows; ++i) text += std::to_string(i) + ",0.5\n";
  const std::string long_id(3 << 20, 'x');
  text += long_id + ",7\n";
  CsvReader reader(WriteTemp("softbench_csv_refills.csv", text));
  std::vector<std::string_view> fields;
  for (int i = 0; i < rows; ++i) {
    ASSERT_TRUE(reader.ReadRow(&fields));
    ASSERT_EQ(fields[0], std::to_string(i));
  }
  ASSERT_TRUE(reader.ReadRow(&fields));
  EXPECT_EQ(fields[0], long_id);
  EXPECT_EQ(fields[1], "7");
  EXPECT_FALSE(reader.ReadRow(&fields));
  EXPECT_NE(ReadAllError("softbench_csv_endless.csv",
                         "a,b\n" + std::string(17 << 20, '1'))
                .find("softbench_csv_endless.csv:2: a line longer than 16 "
                      "MiB; this is not a CSV file"),
            std::string::npos);
}

TEST(CsvReader, ReadsTheDialectsSpreadsheetsWrite) {
  const struct {
    std::string name, text;
    char separator;
  } dialects[] = {
      {"bom.csv", "\xEF\xBB\xBFp1,p2\n1.5,2\n", ','},
      {"quoted.csv", "\"p1\",\"p2\"\n\"1.5\", 2\n", ','},
      {"semicolon.csv", "p1;p2\n1.5;2\n", ';'},
      {"tab.csv", "p1\tp2\n1.5\t2\n", '\t'},
      {"excel.csv", "\xEF\xBB\xBF\"p1\";\"p2\"\r\n1.5;\"2\"\r\n", ';'},
      // Old Mac OS line ends (CR only), as some lab software still writes
      // (issue 30: read as one line, they were "column p3 is missing").
      {"mac.csv", "p1,p2\r1.5,2\r", ','},
      {"mac_no_end.csv", "p1,p2\r# note\r1.5,2", ','},
  };
  for (const auto& dialect : dialects) {
    CsvReader reader(
        WriteTemp("softbench_dialect_" + dialect.name, dialect.text));
    EXPECT_EQ(reader.separator(), dialect.separator) << dialect.name;
    EXPECT_EQ(reader.header(), (std::vector<std::string>{"p1", "p2"}))
        << dialect.name;
    std::vector<std::string_view> fields;
    ASSERT_TRUE(reader.ReadRow(&fields)) << dialect.name;
    ASSERT_EQ(fields.size(), 2u) << dialect.name;
    EXPECT_EQ(ParseDouble(fields[0]), 1.5) << dialect.name;
    EXPECT_EQ(ParseDouble(fields[1]), 2.0) << dialect.name;
  }
}

TEST(CsvReader, RefusesADecimalCommaSayingSo) {
  const std::string message =
      ReadAllError("softbench_decimal_comma.csv", "p1;p2\n1;6,5\n");
  EXPECT_NE(
      message.find(
          "softbench_decimal_comma.csv:2: '6,5' has a decimal "
          "comma; write numbers with a decimal point ('6.5') or declare the "
          "comma with --decimal-comma"),
      std::string::npos)
      << message;
}

TEST(CsvReader, ReadsADeclaredDecimalComma) {
  const struct {
    std::string name, text;
    char separator;
  } dialects[] = {
      {"semicolon.csv", "id;p1;p2\nb,c;6,5;-0,25\n", ';'},
      {"tab.csv", "id\tp1\tp2\nb,c\t6,5\t-0,25\n", '\t'},
      {"quoted.csv", "\"id\";\"p1\";\"p2\"\r\n\"b,c\";\"6,5\";-0,25\r\n", ';'},
      {"one_column.csv", "p1\n6,5\n", ';'},
  };
  for (const auto& dialect : dialects) {
    CsvReader reader(WriteTemp("softbench_comma_" + dialect.name, dialect.text),
                     DecimalMark::kComma);
    EXPECT_EQ(reader.separator(), dialect.separator) << dialect.name;
    std::vector<std::string_view> fields;
    ASSERT_TRUE(reader.ReadRow(&fields)) << dialect.name;
    if (fields.size() == 1) {
      EXPECT_EQ(ParseDouble(fields[0]), 6.5) << dialect.name;
      continue;
    }
    ASSERT_EQ(fields.size(), 3u) << dialect.name;
    // A name with a comma stays as written; numbers come back with points.
    EXPECT_EQ(fields[0], "b,c") << dialect.name;
    EXPECT_EQ(ParseDouble(fields[1]), 6.5) << dialect.name;
    EXPECT_EQ(ParseDouble(fields[2]), -0.25) << dialect.name;
    EXPECT_FALSE(reader.ReadRow(&fields)) << dialect.name;
  }
}

TEST(CsvReader, RefusesAPointOrACommaSeparatorWhenACommaIsDeclared) {
  // "1.234" may be 1234 with a thousands point: never guessed.
  const std::string point = ReadAllError(
      "softbench_comma_point.csv", "p1;p2\n1.234;2\n", DecimalMark::kComma);
  EXPECT_NE(point.find("softbench_comma_point.csv:2: '1.234' has a decimal "
                       "point, but the numbers are declared to have a "
                       "decimal comma (--decimal-comma); write '1,234'"),
            std::string::npos)
      << point;
  const std::string separator = ReadAllError(
      "softbench_comma_separator.csv", "p1,p2\n1,2\n", DecimalMark::kComma);
  EXPECT_NE(separator.find("softbench_comma_separator.csv:1: the header "
                           "separates its columns with ','"),
            std::string::npos)
      << separator;
  // "1.234,5" is neither: the caller's number check names it.
  CsvReader reader(WriteTemp("softbench_comma_both.csv", "p1\n1.234,5\n"),
                   DecimalMark::kComma);
  std::vector<std::string_view> fields;
  ASSERT_TRUE(reader.ReadRow(&fields));
  EXPECT_FALSE(ParseDouble(fields[0]).has_value());
}

TEST(CsvReader, RefusesWhatIsNotACsvFileWithOneLine) {
  EXPECT_NE(ReadAllError("softbench_unclosed.csv", "a,b\n\"1,2\n")
                .find(":2: a quoted field has no closing quote"),
            std::string::npos);
  EXPECT_NE(ReadAllError("softbench_binary.csv", std::string("a\0b\n", 4))
                .find(":1: the header is not text"),
            std::string::npos);
  EXPECT_NE(ReadAllError("softbench_twice.csv", "p1_psi,p1_psi\n1,2\n")
                .find(":1: column 'p1_psi' is given twice"),
            std::string::npos);
  const std::string message =
      InputErrorOf([&] { CsvReader reader("/dev/zero"); });
  EXPECT_NE(message.find("/dev/zero: is a device"), std::string::npos)
      << message;
  EXPECT_THROW(CsvReader(TestScratch().dir().string()), InputError);
}

TEST(CsvField, RoundTripsThroughTheReader) {
  const std::vector<std::string> texts = {"plain", "a,b", "say \"hi\"",
                                          " padded ", ""};
  std::string csv = "x";
  for (size_t i = 1; i < texts.size(); ++i) csv += ",x" + std::to_string(i);
  csv += "\n";
  for (size_t i = 0; i < texts.size(); ++i) {
    csv += (i == 0 ? "" : ",") + CsvField(texts[i]);
  }
  EXPECT_EQ(CsvField("plain"), "plain");
  EXPECT_EQ(CsvField("a,b"), "\"a,b\"");
  CsvReader reader(WriteTemp("softbench_csv_field.csv", csv + "\n"));
  std::vector<std::string_view> fields;
  ASSERT_TRUE(reader.ReadRow(&fields));
  ASSERT_EQ(fields.size(), texts.size());
  for (size_t i = 0; i < texts.size(); ++i) EXPECT_EQ(fields[i], texts[i]);
}

}  // namespace
}  // namespace softbench
