#ifndef SOFTBENCH_UTIL_CSV_H_
#define SOFTBENCH_UTIL_CSV_H_

#include <cstdint>
#include <cstdio>
#include <deque>
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
// The same, writing `*value` and returning whether it parsed: for loops over
// millions of fields, where an optional<double> returned through memory and
// read back whole stalls the load on the two stores that wrote it.
bool ParseDouble(std::string_view text, double* value);

// How a CSV's numbers write their decimal mark.
enum class DecimalMark {
  kPoint,  // "6.5", the default; a decimal comma is refused
  // "6,5", as spreadsheets in many locales export; declared by the user
  // (--decimal-comma), never guessed. Fields are then separated by ';' or a
  // tab, and a number written with a point is refused (the point may be a
  // thousands separator: "1.234,5").
  kComma,
};

// Reads a delimited text file with a header row, one line at a time, through
// a large buffer (multi-gigabyte force logs stream at memory speed). Blank
// lines and lines starting with '#' are skipped; CRLF line ends are accepted.
// The dialects spreadsheets write are read: a UTF-8 byte-order mark, fields
// in double quotes (RFC 4180, "" for a quote inside), and ';' or tab as the
// separator when the header uses it instead of ','. A decimal comma ("6,5")
// is refused with a message saying so, never read as two fields or as 6,
// unless the caller declares it (DecimalMark::kComma): then rows come back
// with decimal points. Errors throw InputError naming the file and line.
class CsvReader {
 public:
  // Opens `path` (a regular file) and reads its header.
  explicit CsvReader(const std::string& path,
                     DecimalMark decimal_mark = DecimalMark::kPoint);

  // The separator the header uses: ',', ';' or '\t'.
  char separator() const { return separator_; }

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
  // Splits line_ into fields_ views, unquoting quoted fields.
  void SplitLine(std::vector<std::string_view>* fields);
  // Throws when a field of a ';' or tab file is a number with a decimal comma.
  void CheckNoDecimalComma(const std::vector<std::string_view>& fields) const;
  // DecimalMark::kComma: rewrites "6,5" as "6.5"; throws on "6.5".
  void ConvertDecimalCommas(std::vector<std::string_view>* fields);
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
  char separator_ = ',';
  // '\n' (with or without a CR before it), or '\r' for a file with old Mac
  // OS line ends, which some lab software still writes.
  char line_end_ = '\n';
  DecimalMark decimal_mark_ = DecimalMark::kPoint;
  // The rewritten numbers of the row last read (DecimalMark::kComma).
  std::deque<std::string> dotted_;
  // The quoted fields' text; a deque, so views stay valid as it grows.
  std::deque<std::string> unquoted_;
};

// Splits one CSV line on commas into views of `line`, trimming spaces.
void SplitCsvLine(std::string_view line, std::vector<std::string_view>* fields);

// `text` as one CSV field (RFC 4180): quoted, with quotes doubled, when it
// holds a comma, a quote, a line end or leading or trailing spaces.
std::string CsvField(std::string_view text);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_CSV_H_
