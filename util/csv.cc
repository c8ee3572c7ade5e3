#include "util/csv.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <cstring>

#include "util/input_error.h"

namespace softbench {
namespace {

std::string_view Trim(std::string_view text) {
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string_view::npos) return {};
  const size_t end = text.find_last_not_of(" \t\r");
  return text.substr(begin, end - begin + 1);
}

}  // namespace

std::optional<double> ParseDouble(std::string_view text) {
  text = Trim(text);
  if (text.empty()) return std::nullopt;
  if (text.front() == '+') text.remove_prefix(1);  // fast_float rejects '+'
  double value = 0.0;
  const auto result =
      fast_float::from_chars(text.data(), text.data() + text.size(), value);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) {
    return std::nullopt;
  }
  return value;
}

void SplitCsvLine(std::string_view line,
                  std::vector<std::string_view>* fields) {
  fields->clear();
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    fields->push_back(Trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

CsvReader::CsvReader(const std::string& path)
    : path_(path),
      file_(std::fopen(path.c_str(), "rb"), &std::fclose),
      buffer_(size_t{1} << 20) {
  if (!file_) {
    throw InputError(path + ": cannot open the file; check the path");
  }
  if (!NextContentLine()) {
    throw InputError(path + ": the file is empty; it needs a header row");
  }
  std::vector<std::string_view> fields;
  SplitCsvLine(line_, &fields);
  for (std::string_view field : fields) header_.emplace_back(field);
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
  if (end_ == buffer_.size()) buffer_.resize(2 * buffer_.size());
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
    const void* newline = std::memchr(begin, '\n', end_ - begin_);
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

bool CsvReader::ReadRow(std::vector<std::string_view>* fields) {
  if (!NextContentLine()) return false;
  SplitCsvLine(line_, fields);
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
