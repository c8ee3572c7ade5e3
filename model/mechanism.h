#ifndef SOFTBENCH_MODEL_MECHANISM_H_
#define SOFTBENCH_MODEL_MECHANISM_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace softbench {

// A rigid head: a free point in the mechanism's y-z plane (thesis 4.1.2).
struct Head {
  std::string name;
  Eigen::Vector2d rest_mm = Eigen::Vector2d::Zero();  // world (y, z) at rest
};

// A fixed support on the outer ring.
struct FixedAnchor {
  std::string name;
  Eigen::Vector2d position_mm = Eigen::Vector2d::Zero();  // world (y, z)
};

// What an actuator's anchor end is attached to.
struct AnchorRef {
  enum class Kind { kFixed, kHead };
  Kind kind = Kind::kFixed;
  int index = 0;  // into Mechanism::fixed_anchors or Mechanism::heads
};

// One bellows actuator from its anchor A to its head H. R = Rx(phi) maps local
// (y, z) to world (y, z), with local +z along the rest axis from A to H
// (model.md). The model takes phi from the rest geometry itself, so that the
// rest state is exactly force-free; `rotation_rad` is the declared nominal
// angle (Eq. 4.1-4.3, 4.7-4.11), checked against the geometry.
struct Actuator {
  std::string name;
  double rotation_rad = 0.0;  // declared phi
  AnchorRef anchor;
  int head = 0;  // index into Mechanism::heads
};

// What Mechanism::Problem() found wrong, and where.
struct MechanismProblem {
  std::string message;
  int actuator = -1;  // index of the actuator at fault, or -1
  int head = -1;      // index of the head at fault, or -1
};

// A network of heads, fixed anchors and actuators; pressures are indexed in
// the order of `actuators` (p1..pN).
struct Mechanism {
  std::string name;
  std::vector<Head> heads;
  std::vector<FixedAnchor> fixed_anchors;
  std::vector<Actuator> actuators;

  // The largest difference [rad] allowed between the declared rotation and
  // the rest axis before the file is considered inconsistent. CAD coordinates
  // are rounded (the floating mechanism's Y, Z put actuators 1-4 at 30.0049
  // deg from the y axis for a nominal 30 deg), so a small mismatch is
  // tolerated.
  static constexpr double kMaxAxisMismatchRad = 1e-3;

  int NumHeads() const { return static_cast<int>(heads.size()); }
  int NumActuators() const { return static_cast<int>(actuators.size()); }
  // Number of unknowns of the equilibrium problem: (y, z) per head.
  int NumUnknowns() const { return 2 * NumHeads(); }

  // Rest position of an actuator's anchor end.
  Eigen::Vector2d AnchorRestPosition(const Actuator& actuator) const;
  // D: rest anchor-to-head distance [mm].
  double RestLength(const Actuator& actuator) const;
  // phi such that Rx(phi) maps local +z onto the rest anchor-to-head axis.
  double RestAxisRotation(const Actuator& actuator) const;

  // Empty when the network is well formed: at least one head and actuator,
  // valid indices, no actuator from a head to itself, finite coordinates, a
  // positive rest length, the declared rotation along the rest axis, and
  // every head tied (possibly through other heads) to a fixed anchor.
  std::optional<MechanismProblem> Problem() const;
};

// Rx(phi) acting on (y, z): [[cos, -sin], [sin, cos]] (model.md, Eq. 4.1-4.3).
Eigen::Matrix2d RotationX(double angle_rad);

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_MECHANISM_H_
