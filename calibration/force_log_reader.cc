#include "calibration/force_log_reader.h"

#include <fmt/format.h>

#include <cmath>
#include <set>

#include "model/units.h"
#include "util/check.h"
#include "util/csv.h"
#include "util/input_error.h"

namespace softbench {
namespace {

constexpr size_t kMaxSkippedExamples = 5;
// Rows between updates of the shared byte counter.
constexpr int64_t kProgressEveryRows = 1 << 16;

int RequireColumn(const CsvReader& reader, const std::string& name,
                  std::string_view role) {
  const int index = reader.ColumnIndex(name);
  if (index >= 0) return index;
  std::string header;
  for (const std::string& column : reader.header()) {
    header += (header.empty() ? "" : ",") + column;
  }
  throw InputError(fmt::format(
      "{}: header: no column '{}' for the {}; the header is '{}'; rename the "
      "column or map it in the manifest (columns/axes)",
      reader.path(), name, role, header));
}

// Parses and checks the rows of a log, one at a time.
class LogRowParser {
 public:
  enum class Row { kEnd, kSkipped, kValid };

  LogRowParser(const std::string& path, const ForceLogColumns& columns,
               const ForceLogReadOptions& options, ForceLogReadSummary* summary,
               std::atomic<int64_t>* bytes_done)
      : reader_(path, options.decimal_mark),
        columns_(columns),
        options_(options),
        summary_(summary),
        bytes_done_(bytes_done),
        time_(RequireColumn(reader_, columns.time, "time")),
        pressure_(RequireColumn(reader_, columns.pressure, "pressure")),
        axial_(RequireColumn(reader_, columns.axial, "axial force")),
        shear_(RequireColumn(reader_, columns.shear, "shear force")) {
    // One column read for two quantities (axial and shear both "fz_n") is
    // a mapping slip that would fit nonsense without a complaint.
    const std::pair<int, const char*> roles[] = {{time_, "time"},
                                                 {pressure_, "pressure"},
                                                 {axial_, "axial force"},
                                                 {shear_, "shear force"}};
    for (size_t i = 0; i < 4; ++i) {
      for (size_t j = i + 1; j < 4; ++j) {
        if (roles[i].first != roles[j].first) continue;
        throw InputError(fmt::format(
            "{}: header: the {} and the {} are both column '{}'; map each "
            "to its own column (the manifest's columns/axes, or --axial and "
            "--shear)",
            path, roles[i].second, roles[j].second,
            reader_.header()[roles[i].first]));
      }
    }
  }

  ~LogRowParser() { ReportBytes(); }

  CsvReader& reader() { return reader_; }
  const std::vector<std::string_view>& fields() const { return fields_; }

  Row Next() {
    if (!reader_.ReadRow(&fields_)) return Row::kEnd;
    if (++rows_since_report_ == kProgressEveryRows) ReportBytes();
    double time = 0.0, pressure = 0.0, axial = 0.0, shear = 0.0;
    // In order, stopping at the first that fails: the row is skipped once,
    // named by its first bad field (as when all four were parsed).
    if (!Number(time_, "time", &time) ||
        !Number(pressure_, "pressure", &pressure) ||
        !Number(axial_, "axial force", &axial) ||
        !Number(shear_, "shear force", &shear)) {
      return Row::kSkipped;
    }
    pressure_mpa = pressure * columns_.mpa_per_unit;
    axial_n = columns_.axial_sign * axial;
    shear_n = columns_.shear_sign * shear;
    if (pressure_mpa < options_.min_pressure_mpa ||
        pressure_mpa > options_.max_pressure_mpa) {
      return Skip(fmt::format(
          "pressure {} is outside {:.4g} .. {:.4g} in the log's unit (is the "
          "manifest's pressure_unit, or --pressure-unit, the unit the log "
          "is in?)",
          pressure, options_.min_pressure_mpa / columns_.mpa_per_unit,
          options_.max_pressure_mpa / columns_.mpa_per_unit));
    }
    if (std::abs(axial_n) > options_.max_abs_force_n ||
        std::abs(shear_n) > options_.max_abs_force_n) {
      return Skip(fmt::format("a force beyond +-{} N (the sensor's range)",
                              options_.max_abs_force_n));
    }
    time_s = time;
    ++summary_->rows;
    return Row::kValid;
  }

  // Called for each valid row once it is known which test it belongs to.
  void CheckTimeOrder() {
    if (time_s < last_time_s_) {
      throw InputError(fmt::format(
          "{}time {} s is before the previous row's {} s; sort the log by "
          "time",
          reader_.Where(), time_s, last_time_s_));
    }
    last_time_s_ = time_s;
  }
  // Keeps the row last read when it is the n-th of its test (`count`
  // rows so far) for the row-wise fit.
  void KeepRow(int64_t count, int test, std::vector<ForceRow>* kept) const {
    if (kept != nullptr && options_.keep_every_nth_row > 0 &&
        count % options_.keep_every_nth_row == 0) {
      kept->push_back({pressure_mpa, axial_n, shear_n, test});
    }
  }
  // A new test starts (combined logs): time may start again.
  void RestartTime() { last_time_s_ = -INFINITY; }

  double time_s = 0.0;
  double pressure_mpa = 0.0;
  double axial_n = 0.0;
  double shear_n = 0.0;

 private:
  bool Number(int column, std::string_view what, double* value) {
    if (ParseDouble(fields_[column], value) && std::isfinite(*value)) {
      return true;
    }
    Skip(fmt::format("{} '{}' is not a finite number", what, fields_[column]));
    return false;
  }

  Row Skip(const std::string& why) {
    // One row may fail several checks; count it once.
    if (skipped_line_ != reader_.line_number()) {
      skipped_line_ = reader_.line_number();
      ++summary_->rows_skipped;
      if (summary_->skipped_examples.size() < kMaxSkippedExamples) {
        summary_->skipped_examples.push_back(reader_.Where() + why);
      }
    }
    return Row::kSkipped;
  }

  void ReportBytes() {
    if (bytes_done_ != nullptr) {
      bytes_done_->fetch_add(reader_.bytes_read() - bytes_reported_);
    }
    bytes_reported_ = reader_.bytes_read();
    rows_since_report_ = 0;
  }

  CsvReader reader_;
  const ForceLogColumns& columns_;
  const ForceLogReadOptions& options_;
  ForceLogReadSummary* summary_;
  std::atomic<int64_t>* bytes_done_;
  int time_, pressure_, axial_, shear_;
  std::vector<std::string_view> fields_;
  double last_time_s_ = -INFINITY;
  int skipped_line_ = 0;
  int64_t rows_since_report_ = 0;
  int64_t bytes_reported_ = 0;
};

// Ends a test: the checks that need all its rows.
void FinishTest(const std::string& path, const ForceLogReadOptions& options,
                const ForceLogReadSummary& file_summary,
                const ForceTestAccumulator& accumulator, ForceTest* test) {
  const int64_t seen = file_summary.rows + file_summary.rows_skipped;
  if (file_summary.rows_skipped >
      options.max_skipped_fraction * static_cast<double>(seen)) {
    throw InputError(fmt::format(
        "{}: {} of {} rows are unusable (more than {:.3g} %), the first: {}; "
        "fix the export",
        path, file_summary.rows_skipped, seen,
        100.0 * options.max_skipped_fraction,
        file_summary.skipped_examples.front()));
  }
  test->statistics = accumulator.Statistics();
  if (accumulator.count() == 0 || test->statistics.ZeroPressure().count == 0) {
    throw InputError(fmt::format(
        "{}: test '{}' has no rows at zero pressure (<= {} kPa); the static "
        "offset needs the rows logged before the ramp starts",
        path, test->id, options.binning.zero_pressure_mpa / kMpaPerKpa));
  }
}

void CheckOptions(const ForceLogReadOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
}

}  // namespace

std::optional<std::string> ForceLogReadOptions::Problem() const {
  if (std::optional<std::string> problem = binning.Problem()) return problem;
  if (!(max_abs_force_n > 0.0)) return "max_abs_force_n must be > 0";
  if (!(min_pressure_mpa < max_pressure_mpa)) {
    return "min_pressure_mpa must be below max_pressure_mpa";
  }
  if (!(max_skipped_fraction >= 0.0 && max_skipped_fraction <= 1.0)) {
    return "max_skipped_fraction must be in [0, 1]";
  }
  if (keep_every_nth_row < 0) return "keep_every_nth_row must be >= 0";
  return std::nullopt;
}

void ForceLogReadSummary::Merge(const ForceLogReadSummary& other) {
  rows += other.rows;
  rows_skipped += other.rows_skipped;
  for (const std::string& example : other.skipped_examples) {
    if (skipped_examples.size() < kMaxSkippedExamples) {
      skipped_examples.push_back(example);
    }
  }
}

void ReadForceTestCsv(const std::string& path, const ForceLogColumns& columns,
                      const ForceLogReadOptions& options, int test_index,
                      ForceTest* test, ForceLogReadSummary* summary,
                      std::vector<ForceRow>* kept_rows,
                      std::atomic<int64_t>* bytes_done) {
  CheckOptions(options);
  ForceLogReadSummary file_summary;
  ForceTestAccumulator accumulator(options.binning);
  {
    LogRowParser parser(path, columns, options, &file_summary, bytes_done);
    for (LogRowParser::Row row;
         (row = parser.Next()) != LogRowParser::Row::kEnd;) {
      if (row != LogRowParser::Row::kValid) continue;
      parser.CheckTimeOrder();
      accumulator.Add(parser.pressure_mpa, parser.axial_n, parser.shear_n);
      parser.KeepRow(accumulator.count(), test_index, kept_rows);
    }
  }
  test->source = path;
  FinishTest(path, options, file_summary, accumulator, test);
  summary->Merge(file_summary);
}

// A combined log's new test, from its first row: its id and configuration
// (`columns`: nominal dL, nominal theta, then the measured ones or -1),
// refused when no clamp can hold it.
ForceTest TestOfRow(LogRowParser* parser, const std::vector<int>& columns,
                    const std::string& path) {
  const CsvReader& reader = parser->reader();
  const auto number = [&](int column) {
    const std::string_view field = parser->fields()[column];
    const std::optional<double> value = ParseDouble(field);
    if (!value || !std::isfinite(*value)) {
      throw InputError(fmt::format("{}{} '{}' is not a finite number",
                                   reader.Where(), reader.header()[column],
                                   field));
    }
    return *value;
  };
  ForceTest test;
  test.id = parser->fields()[reader.ColumnIndex("test_id")];
  test.source = path;
  test.nominal_delta_length_mm = number(columns[0]);
  test.nominal_theta_rad = DegToRad(number(columns[1]));
  if (columns[2] >= 0) test.measured_delta_length_mm = number(columns[2]);
  if (columns[3] >= 0) test.measured_theta_rad = DegToRad(number(columns[3]));
  if (const auto problem = ImplausibleTest(test)) {
    throw InputError(
        fmt::format("{}test '{}': {}", reader.Where(), test.id, *problem));
  }
  return test;
}

std::vector<ForceTest> ReadCombinedForceLog(const std::string& path,
                                            const ForceLogColumns& columns,
                                            const ForceLogReadOptions& options,
                                            ForceLogReadSummary* summary,
                                            std::vector<ForceRow>* kept_rows,
                                            std::atomic<int64_t>* bytes_done) {
  CheckOptions(options);
  ForceLogReadSummary file_summary;
  LogRowParser parser(path, columns, options, &file_summary, bytes_done);
  const CsvReader& reader = parser.reader();
  const int id_column = RequireColumn(reader, "test_id", "test id");
  const int length_column =
      RequireColumn(reader, "delta_length_mm", "nominal change of length");
  const int theta_column =
      RequireColumn(reader, "theta_deg", "nominal orientation angle");
  const int measured_length_column =
      reader.ColumnIndex("measured_delta_length_mm");
  const int measured_theta_column = reader.ColumnIndex("measured_theta_deg");

  std::vector<ForceTest> tests;
  std::set<std::string> finished_ids;
  std::optional<ForceTestAccumulator> accumulator;
  // The configuration fields' text in the current test's first row.
  std::vector<std::string> configuration_text;
  const std::vector<int> configuration_columns = {length_column, theta_column,
                                                  measured_length_column,
                                                  measured_theta_column};
  const auto finish = [&] {
    if (!accumulator) return;
    ForceTest& test = tests.back();
    FinishTest(path, options, file_summary, *accumulator, &test);
    finished_ids.insert(test.id);
  };

  for (LogRowParser::Row row;
       (row = parser.Next()) != LogRowParser::Row::kEnd;) {
    const std::string_view id = parser.fields()[id_column];
    if (tests.empty() || id != tests.back().id) {
      finish();
      if (finished_ids.count(std::string(id)) != 0) {
        throw InputError(fmt::format(
            "{}test '{}' appears again after other tests; keep each test's "
            "rows together",
            reader.Where(), id));
      }
      tests.push_back(TestOfRow(&parser, configuration_columns, path));
      configuration_text.clear();
      for (int column : configuration_columns) {
        configuration_text.emplace_back(column >= 0 ? parser.fields()[column]
                                                    : std::string_view());
      }
      accumulator.emplace(options.binning);
      parser.RestartTime();
    } else {
      for (size_t k = 0; k < configuration_columns.size(); ++k) {
        const int column = configuration_columns[k];
        if (column >= 0 && parser.fields()[column] != configuration_text[k]) {
          throw InputError(fmt::format(
              "{}{} changes within test '{}' ('{}', was '{}'); give each "
              "configuration its own test_id",
              reader.Where(), reader.header()[column], id,
              parser.fields()[column], configuration_text[k]));
        }
      }
    }
    if (row != LogRowParser::Row::kValid) continue;
    parser.CheckTimeOrder();
    accumulator->Add(parser.pressure_mpa, parser.axial_n, parser.shear_n);
    parser.KeepRow(accumulator->count(), static_cast<int>(tests.size()) - 1,
                   kept_rows);
  }
  finish();
  if (tests.empty()) {
    throw InputError(path + ": no data rows; the log is empty");
  }
  summary->Merge(file_summary);
  return tests;
}

}  // namespace softbench
