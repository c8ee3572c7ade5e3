#ifndef SOFTBENCH_MODEL_WORKSPACE_H_
#define SOFTBENCH_MODEL_WORKSPACE_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "model/characterised_range.h"
#include "model/equilibrium.h"

namespace softbench {

struct WorkspaceOptions {
  // Pressure levels [MPa] applied to every actuator; the map holds every
  // combination (levels^actuators configurations), as in thesis fig. 4.6.
  std::vector<double> pressure_levels_mpa;
  // Worker threads; 0 uses every hardware thread.
  int num_threads = 0;
  EquilibriumOptions equilibrium;
  // When set, each converged configuration is checked against the range the
  // constants were characterised over (WorkspaceMap::in_range) and, where
  // its pressures lie beyond it, against the mechanism's reach
  // (WorkspaceMap::within_reach, a bounded inverse solve each), on the
  // workers that solve it.
  std::optional<CharacterisedRange> range;

  std::optional<std::string> Problem() const;
};

// num_intervals + 1 levels from 0 to max_mpa inclusive, evenly spaced (level
// i is max_mpa * i / num_intervals, so the top level is exactly max_mpa).
std::vector<double> EvenPressureLevels(double max_mpa, int num_intervals);

// Extents of one head's displacement over the converged configurations.
struct HeadExtents {
  Eigen::Vector2d min_mm = Eigen::Vector2d::Zero();  // (y, z)
  Eigen::Vector2d max_mm = Eigen::Vector2d::Zero();
};

struct WorkspaceMap {
  // Row i: the pressures [MPa] of configuration i, in lexicographic order of
  // level indices (p1 slowest, pN fastest).
  Eigen::MatrixXd pressures_mpa;
  // Row i: the heads' displacements (y1, z1, y2, z2, ...) [mm].
  Eigen::MatrixXd displacements_mm;
  std::vector<EquilibriumSummary> summaries;
  int num_not_converged = 0;
  // Per row: 0 when it converged beyond WorkspaceOptions::range (the model
  // extrapolates there; OutsideCharacterisedRange says why), else 1.
  std::vector<uint8_t> in_range;
  int num_outside_range = 0;
  // Per row, with WorkspaceOptions::range: 0 when the heads lie beyond the
  // mechanism's reach (ReachOfPrediction: no pressures in the range hold
  // them there, or it could not be shown), else 1. Rows that did not
  // converge are 0.
  std::vector<uint8_t> within_reach;
  int num_beyond_reach = 0;

  // Extents per head over converged configurations only.
  std::vector<HeadExtents> Extents() const;
};

// Solves every combination of pressure levels. Configurations are visited in
// reflected Gray-code order, so each solve starts from the solution of a
// neighbour that differs by one level of one actuator, moved along its
// tangent (EquilibriumSolver::PredictSolution); threads take contiguous runs
// of that order. A warm start that fails is retried from the
// rest state before it is reported as not converged.
WorkspaceMap ComputeWorkspace(const EquilibriumProblem& problem,
                              const WorkspaceOptions& options);
// The same into *map, reusing its storage when it already has the map's size:
// a caller that sweeps many maps (other constants, other levels) then pays
// for the memory once, not per map.
void ComputeWorkspace(const EquilibriumProblem& problem,
                      const WorkspaceOptions& options, WorkspaceMap* map);

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_WORKSPACE_H_
