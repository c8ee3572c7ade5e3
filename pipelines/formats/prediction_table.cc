#include "pipelines/formats/prediction_table.h"

#include <fmt/format.h>

namespace softbench {

PredictionTable::PredictionTable(const Mechanism& mechanism,
                                 std::string_view pressure_unit) {
  for (int a = 1; a <= mechanism.NumActuators(); ++a) {
    text_ += fmt::format("p{}_{},", a, pressure_unit);
  }
  for (int h = 1; h <= mechanism.NumHeads(); ++h) {
    text_ += fmt::format("y{0}_mm,z{0}_mm,", h);
  }
  text_ += "converged,residual_n,in_range,within_reach\n";
}

void PredictionTable::AddRow(const Eigen::VectorXd& pressures_in_unit,
                             const Eigen::VectorXd& displacements_mm,
                             const EquilibriumSummary& summary, bool in_range,
                             bool within_reach) {
  for (double p : pressures_in_unit) text_ += fmt::format("{},", p);
  for (double d : displacements_mm) {
    text_ += summary.converged() ? fmt::format("{:.6f},", d) : "nan,";
  }
  text_ += fmt::format("{},{:.3e},{},{}\n", summary.converged() ? 1 : 0,
                       summary.max_residual_n, in_range ? 1 : 0,
                       within_reach ? 1 : 0);
}

}  // namespace softbench
