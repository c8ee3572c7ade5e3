#ifndef SOFTBENCH_UTIL_CSV_H_
#define SOFTBENCH_UTIL_CSV_H_

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace softbench {

// Parses a whole decimal number (fast_float): leading and trailing spaces are
// allowed, anything else makes it fail. Accepts "nan"/"inf" spellings, so the
// caller decides whether non-finite values are allowed.
std::optional<double> ParseDouble(std::string_view text);

// Reads a comma-separated file with a header row, one line at a time, through
// a large buffer (multi-gigabyte force logs stream at memory speed). Blank
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

  // Reads the next data row into `fields` (views valid until the next call);
  // false at the end of the file. A row whose field count differs from the
  // header's throws InputError.
  bool ReadRow(std::vector<std::string_view>* fields);
  // 1-based line number of the row last returned.
  int line_number() const { return line_number_; }

  // Bytes consumed so far (for progress bars).
  int64_t bytes_read() const { return bytes_read_; }

  // "file:line: " for messages about the row last returned.
  std::string Where() const;

 private:
  bool NextContentLine();
  // Reads more of the file after the unconsumed bytes; false at its end.
  bool Refill();

  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::vector<char> buffer_;
  size_t begin_ = 0;  // first unconsumed byte of buffer_
  size_t end_ = 0;    // one past the last valid byte of buffer_
  bool at_eof_ = false;
  int64_t bytes_read_ = 0;
  std::string_view line_;
  std::vector<std::string> header_;
  int line_number_ = 0;
};

// Splits one CSV line on commas into views of `line`, trimming spaces.
void SplitCsvLine(std::string_view line, std::vector<std::string_view>* fields);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_CSV_H_
