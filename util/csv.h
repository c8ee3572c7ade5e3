#ifndef SOFTBENCH_UTIL_CSV_H_
#define SOFTBENCH_UTIL_CSV_H_

#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace softbench {

// Parses a whole decimal number (fast_float): leading and trailing spaces are
// allowed, anything else makes it fail. Accepts "nan"/"inf" spellings, so the
// caller decides whether non-finite values are allowed.
std::optional<double> ParseDouble(std::string_view text);

// Reads a comma-separated file with a header row, one line at a time. Blank
// lines and lines starting with '#' are skipped; CRLF line ends are accepted.
// Errors throw InputError naming the file and line.
class CsvReader {
 public:
  // Opens `path` and reads its header.
  explicit CsvReader(const std::string& path);

  const std::string& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }
  // Index of a header column, or -1.
  int ColumnIndex(std::string_view name) const;

  // Reads the next data row into `fields`; false at the end of the file. A
  // row whose field count differs from the header's throws InputError.
  bool ReadRow(std::vector<std::string_view>* fields);
  // 1-based line number of the row last returned.
  int line_number() const { return line_number_; }

  // "file:line: " for messages about the row last returned.
  std::string Where() const;

 private:
  bool NextContentLine();

  std::string path_;
  std::ifstream stream_;
  std::string line_;
  std::vector<std::string> header_;
  int line_number_ = 0;
};

// Splits one CSV line on commas into views of `line`, trimming spaces.
void SplitCsvLine(std::string_view line, std::vector<std::string_view>* fields);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_CSV_H_
