#include "tests/support/rendered_truth.h"

#include <string_view>

#include "util/check.h"
#include "util/csv.h"
#include "util/statistics.h"

namespace softbench {
namespace {

double Field(const std::vector<std::string_view>& fields, int column) {
  const std::optional<double> value = ParseDouble(fields[column]);
  SOFTBENCH_CHECK(value.has_value()) << "truth field " << fields[column];
  return *value;
}

}  // namespace

RenderedTruth ReadRenderedTruth(const std::string& path) {
  CsvReader reader(path);
  std::vector<int> y, z, u, v;
  for (int head = 1;
       reader.ColumnIndex("y" + std::to_string(head) + "_mm") >= 0; ++head) {
    const std::string n = std::to_string(head);
    y.push_back(reader.ColumnIndex("y" + n + "_mm"));
    z.push_back(reader.ColumnIndex("z" + n + "_mm"));
    u.push_back(reader.ColumnIndex("u" + n + "_px"));
    v.push_back(reader.ColumnIndex("v" + n + "_px"));
  }
  const int time = reader.ColumnIndex("time_s");
  const int dx = reader.ColumnIndex("camera_dx_px");
  const int dy = reader.ColumnIndex("camera_dy_px");
  const int roll = reader.ColumnIndex("camera_roll_rad");
  SOFTBENCH_CHECK(!y.empty() && time >= 0 && dx >= 0 && dy >= 0 && roll >= 0)
      << path << " is not a render's truth file";
  RenderedTruth truth;
  std::vector<std::string_view> fields;
  while (reader.ReadRow(&fields)) {
    truth.time_s.push_back(Field(fields, time));
    std::vector<Eigen::Vector2d> displacement, position;
    for (size_t h = 0; h < y.size(); ++h) {
      displacement.emplace_back(Field(fields, y[h]), Field(fields, z[h]));
      position.emplace_back(Field(fields, u[h]), Field(fields, v[h]));
    }
    truth.displacement_mm.push_back(displacement);
    truth.position_px.push_back(position);
    truth.camera_shift_px.emplace_back(Field(fields, dx), Field(fields, dy));
    truth.camera_roll_rad.push_back(Field(fields, roll));
  }
  return truth;
}

Eigen::VectorXd RenderedTruth::MedianDisplacementMm(double start_s,
                                                    double end_s) const {
  const int num_heads = NumHeads();
  std::vector<std::vector<double>> values(2 * num_heads);
  for (size_t i = 0; i < time_s.size(); ++i) {
    if (time_s[i] < start_s || time_s[i] >= end_s) continue;
    for (int h = 0; h < num_heads; ++h) {
      values[2 * h].push_back(displacement_mm[i][h].x());
      values[2 * h + 1].push_back(displacement_mm[i][h].y());
    }
  }
  Eigen::VectorXd median(2 * num_heads);
  for (int k = 0; k < 2 * num_heads; ++k) {
    SOFTBENCH_CHECK(!values[k].empty())
        << "no truth frame in [" << start_s << ", " << end_s << ") s";
    median[k] = Median(values[k]);
  }
  return median;
}

}  // namespace softbench
