#include "util/csv.h"

#include <fast_float/fast_float.h>
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "util/input_error.h"
#include "util/input_file.h"

namespace softbench {
namespace {

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Written out rather than find_first_not_of, which searches the set of blanks
// once per character: trimming every field of a 24-million-row log is hot.
std::string_view Trim(std::string_view text) {
  const char* begin = text.data();
  const char* end = begin + text.size();
  while (begin != end && IsBlank(*begin)) ++begin;
  while (end != begin && IsBlank(end[-1])) --end;
  return {begin, static_cast<size_t>(end - begin)};
}

// Views of the `separator`-separated fields of `line`, trimmed. The
// separators are found 16 bytes at a time (SSE2, in every x86-64 CPU): on a
// log's short numbers a search per field, or a branch per byte, costs more
// than the number's parse.
void SplitOn(std::string_view line, char separator,
             std::vector<std::string_view>* fields) {
  fields->clear();
  const char* start = line.data();
  const char* const end = start + line.size();
  const char* p = start;
  const auto field_until = [&](const char* separator_at) {
    fields->push_back(Trim({start, static_cast<size_t>(separator_at - start)}));
    start = separator_at + 1;
  };
#if defined(__SSE2__)
  const __m128i separators = _mm_set1_epi8(separator);
  for (; end - p >= 16; p += 16) {
    const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
    auto mask = static_cast<uint32_t>(
        _mm_movemask_epi8(_mm_cmpeq_epi8(bytes, separators)));
    for (; mask != 0; mask &= mask - 1) field_until(p + std::countr_zero(mask));
  }
#endif
  while (const void* hit = std::memchr(p, separator, end - p)) {
    p = static_cast<const char*>(hit);
    field_until(p++);
  }
  fields->push_back(Trim({start, static_cast<size_t>(end - start)}));
}

// The header's separator: ',' unless it has none and has ';' or tabs
// (spreadsheets in locales with a decimal comma write ';'). With a declared
// decimal comma, ';' unless the header uses tabs.
char DetectSeparator(std::string_view header, DecimalMark decimal_mark) {
  if (decimal_mark == DecimalMark::kComma) {
    const bool tabs = header.find('\t') != std::string_view::npos &&
                      header.find(';') == std::string_view::npos;
    return tabs ? '\t' : ';';
  }
  if (header.find(',') != std::string_view::npos) return ',';
  if (header.find(';') != std::string_view::npos) return ';';
  if (header.find('\t') != std::string_view::npos) return '\t';
  return ',';
}

constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

// A line longer than this is not a CSV row (a binary file or /dev/zero).
constexpr size_t kMaxLineBytes = size_t{16} << 20;

// "6,5" or "-0,25": a number written with a decimal comma.
bool IsDecimalCommaNumber(std::string_view field) {
  const size_t comma = field.find(',');
  if (comma == std::string_view::npos) return false;
  std::string dotted(field);
  dotted[comma] = '.';
  return ParseDouble(dotted).has_value();
}

}  // namespace

bool ParseDouble(std::string_view text, double* value) {
  text = Trim(text);
  if (text.empty()) return false;
  if (text.front() == '+') text.remove_prefix(1);  // fast_float rejects '+'
  const auto result =
      fast_float::from_chars(text.data(), text.data() + text.size(), *value);
  return result.ec == std::errc() && result.ptr == text.data() + text.size();
}

std::optional<double> ParseDouble(std::string_view text) {
  double value = 0.0;
  if (!ParseDouble(text, &value)) return std::nullopt;
  return value;
}

void SplitCsvLine(std::string_view line,
                  std::vector<std::string_view>* fields) {
  SplitOn(line, ',', fields);
}

std::string CsvField(std::string_view text) {
  const bool plain = text.find_first_of(",\"\r\n") == std::string_view::npos &&
                     Trim(text).size() == text.size();
  if (plain) return std::string(text);
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

CsvReader::CsvReader(const std::string& path, DecimalMark decimal_mark)
    : path_(path), file_(nullptr, &std::fclose), decimal_mark_(decimal_mark) {
  // A buffer of 1 MiB streams a long log at memory speed; a short file (a
  // pressure table) gets one its size instead of a megabyte to clear.
  const int64_t bytes = CheckInputFile(path, "CSV");
  buffer_.resize(static_cast<size_t>(
      std::clamp<int64_t>(bytes + 1, int64_t{4} << 10, int64_t{1} << 20)));
  file_.reset(std::fopen(path.c_str(), "rb"));
  if (!file_) {
    throw InputError(path + ": cannot open the file; check its permissions");
  }
  // Line ends from the first block: a CR followed by anything but LF ends
  // lines on its own (old Mac OS); read as LF, such a file is one long line.
  Refill();
  const auto* first_cr =
      static_cast<const char*>(std::memchr(buffer_.data(), '\r', end_));
  if (first_cr != nullptr && first_cr + 1 < buffer_.data() + end_ &&
      first_cr[1] != '\n') {
    line_end_ = '\r';
  }
  if (!NextContentLine()) {
    throw InputError(path + ": the file is empty; it needs a header row");
  }
  if (line_.starts_with(kByteOrderMark)) line_.remove_prefix(3);
  if (const std::optional<NonText> non_text = FindNonText(line_)) {
    throw InputError(Where() + "the header is not text (" + non_text->problem +
                     "); is this a CSV file?");
  }
  separator_ = DetectSeparator(line_, decimal_mark_);
  if (decimal_mark_ == DecimalMark::kComma &&
      line_.find(',') != std::string_view::npos) {
    throw InputError(Where() +
                     "the header separates its columns with ',', but the "
                     "numbers are declared to have a decimal comma; "
                     "separate columns with ';' or tabs, or drop "
                     "--decimal-comma");
  }
  std::vector<std::string_view> fields;
  SplitLine(&fields);
  for (std::string_view field : fields) {
    if (!field.empty() &&
        std::find(header_.begin(), header_.end(), field) != header_.end()) {
      throw InputError(fmt::format("{}column '{}' is given twice; keep one",
                                   Where(), field));
    }
    header_.emplace_back(field);
  }
}

int CsvReader::ColumnIndex(std::string_view name) const {
  for (size_t i = 0; i < header_.size(); ++i) {
    if (header_[i] == name) return static_cast<int>(i);
  }
  return -1;
}

bool CsvReader::Refill() {
  if (at_eof_) return false;
  // Keep the unconsumed tail (a partial line); grow when it fills the buffer.
  std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
  end_ -= begin_;
  begin_ = 0;
  if (end_ == buffer_.size()) {
    if (buffer_.size() >= kMaxLineBytes) {
      throw InputError(fmt::format(
          "{}:{}: a line longer than {} MiB; this is not a CSV file", path_,
          line_number_ + 1, kMaxLineBytes >> 20));
    }
    buffer_.resize(2 * buffer_.size());
  }
  const size_t got =
      std::fread(buffer_.data() + end_, 1, buffer_.size() - end_, file_.get());
  if (got == 0) {
    if (std::ferror(file_.get())) {
      throw InputError(path_ + ":" + std::to_string(line_number_ + 1) +
                       ": read error");
    }
    at_eof_ = true;
    return false;
  }
  end_ += got;
  return true;
}

bool CsvReader::NextContentLine() {
  for (;;) {
    const char* begin = buffer_.data() + begin_;
    const void* newline = std::memchr(begin, line_end_, end_ - begin_);
    size_t length = 0;
    if (newline != nullptr) {
      length = static_cast<const char*>(newline) - begin;
    } else if (Refill()) {
      continue;
    } else if (begin_ < end_) {
      length = end_ - begin_;  // last line without a line end
    } else {
      return false;
    }
    const size_t consumed = std::min(length + 1, end_ - begin_);
    line_ = std::string_view(buffer_.data() + begin_, length);
    begin_ += consumed;
    bytes_read_ += static_cast<int64_t>(consumed);
    ++line_number_;
    const std::string_view content = Trim(line_);
    if (!content.empty() && content.front() != '#') return true;
  }
}

void CsvReader::SplitLine(std::vector<std::string_view>* fields) {
  if (line_.find('"') == std::string_view::npos) {  // the fast, usual case
    SplitOn(line_, separator_, fields);
    return;
  }
  // RFC 4180: a field in quotes may hold separators and "" for a quote.
  fields->clear();
  unquoted_.clear();
  size_t i = 0;
  for (;;) {
    while (i < line_.size() && (line_[i] == ' ' || line_[i] == '\t') &&
           line_[i] != separator_) {
      ++i;
    }
    if (i < line_.size() && line_[i] == '"') {
      std::string& text = unquoted_.emplace_back();
      for (++i;; ++i) {
        if (i >= line_.size()) {
          throw InputError(Where() +
                           "a quoted field has no closing quote; close it "
                           "on the same line");
        }
        if (line_[i] == '"') {
          if (i + 1 < line_.size() && line_[i + 1] == '"') {
            text += '"';
            ++i;
            continue;
          }
          ++i;
          break;
        }
        text += line_[i];
      }
      const size_t end = line_.find(separator_, i);
      if (!Trim(line_.substr(i, end - i)).empty()) {
        throw InputError(Where() +
                         "text after a quoted field's closing quote; quote "
                         "the whole field");
      }
      fields->push_back(text);
      if (end == std::string_view::npos) return;
      i = end + 1;
    } else {
      const size_t end = line_.find(separator_, i);
      fields->push_back(Trim(line_.substr(i, end - i)));
      if (end == std::string_view::npos) return;
      i = end + 1;
    }
  }
}

void CsvReader::CheckNoDecimalComma(
    const std::vector<std::string_view>& fields) const {
  if (separator_ == ',') return;
  for (std::string_view field : fields) {
    if (IsDecimalCommaNumber(field)) {
      throw InputError(fmt::format(
          "{}'{}' has a decimal comma; write numbers with a decimal point "
          "('{}') or declare the comma with --decimal-comma",
          Where(), field, std::string(field).replace(field.find(','), 1, ".")));
    }
  }
}

void CsvReader::ConvertDecimalCommas(std::vector<std::string_view>* fields) {
  dotted_.clear();
  for (std::string_view& field : *fields) {
    if (field.find(',') != std::string_view::npos) {
      if (IsDecimalCommaNumber(field)) {
        std::string& dotted = dotted_.emplace_back(field);
        dotted[dotted.find(',')] = '.';
        field = dotted;
      }
    } else if (field.find('.') != std::string_view::npos &&
               ParseDouble(field)) {
      throw InputError(fmt::format(
          "{}'{}' has a decimal point, but the numbers are declared to have "
          "a decimal comma (--decimal-comma); write '{}' (a point is not "
          "read as a thousands separator either)",
          Where(), field, std::string(field).replace(field.find('.'), 1, ",")));
    }
  }
}

bool CsvReader::ReadRow(std::vector<std::string_view>* fields) {
  if (!NextContentLine()) return false;
  SplitLine(fields);
  if (decimal_mark_ == DecimalMark::kComma) {
    ConvertDecimalCommas(fields);
  } else {
    CheckNoDecimalComma(*fields);
  }
  if (fields->size() != header_.size()) {
    throw InputError(Where() + "has " + std::to_string(fields->size()) +
                     " fields but the header has " +
                     std::to_string(header_.size()) +
                     "; give every row one value per column");
  }
  return true;
}

std::string CsvReader::Where() const {
  return path_ + ":" + std::to_string(line_number_) + ": ";
}

}  // namespace softbench
