#include "model/mechanism.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>

#include "model/units.h"

namespace softbench {
namespace {

// Union-find root of a head, used to check that every head reaches a fixed
// anchor.
int Root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

std::string Degrees(double radians) {
  char text[32];
  // "+ 0.0" turns a negative zero into "0".
  std::snprintf(text, sizeof(text), "%.6g", RadToDeg(radians) + 0.0);
  return text;
}

}  // namespace

Eigen::Matrix2d RotationX(double angle_rad) {
  const double c = std::cos(angle_rad);
  const double s = std::sin(angle_rad);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

Eigen::Vector2d Mechanism::AnchorRestPosition(const Actuator& actuator) const {
  return actuator.anchor.kind == AnchorRef::Kind::kFixed
             ? fixed_anchors[actuator.anchor.index].position_mm
             : heads[actuator.anchor.index].rest_mm;
}

double Mechanism::RestLength(const Actuator& actuator) const {
  return (heads[actuator.head].rest_mm - AnchorRestPosition(actuator)).norm();
}

double Mechanism::RestAxisRotation(const Actuator& actuator) const {
  // Rx(phi) * (0, 1) = (-sin phi, cos phi) = axis / |axis|.
  const Eigen::Vector2d axis =
      heads[actuator.head].rest_mm - AnchorRestPosition(actuator);
  return std::atan2(-axis.x(), axis.y());
}

std::optional<MechanismProblem> Mechanism::Problem() const {
  if (heads.empty()) return MechanismProblem{"the mechanism has no heads"};
  if (actuators.empty()) {
    return MechanismProblem{"the mechanism has no actuators"};
  }
  for (int h = 0; h < NumHeads(); ++h) {
    if (!heads[h].rest_mm.allFinite()) {
      return MechanismProblem{
          "head '" + heads[h].name + "' has a non-finite rest position", -1, h};
    }
  }
  for (const FixedAnchor& anchor : fixed_anchors) {
    if (!anchor.position_mm.allFinite()) {
      return MechanismProblem{"anchor '" + anchor.name +
                              "' has a non-finite position"};
    }
  }
  // Heads joined (through actuators) to a fixed anchor share the root
  // NumHeads(); a head left in another set could float away.
  std::vector<int> parent(heads.size() + 1);
  std::iota(parent.begin(), parent.end(), 0);
  const int ground = NumHeads();
  for (int k = 0; k < NumActuators(); ++k) {
    const Actuator& actuator = actuators[k];
    const std::string where = "actuator '" + actuator.name + "'";
    const auto problem = [k](std::string message) {
      return MechanismProblem{std::move(message), k};
    };
    if (actuator.head < 0 || actuator.head >= NumHeads()) {
      return problem(where + " names a head that does not exist");
    }
    const bool fixed = actuator.anchor.kind == AnchorRef::Kind::kFixed;
    const int limit =
        fixed ? static_cast<int>(fixed_anchors.size()) : NumHeads();
    if (actuator.anchor.index < 0 || actuator.anchor.index >= limit) {
      return problem(where + " names an anchor that does not exist");
    }
    if (!fixed && actuator.anchor.index == actuator.head) {
      return problem(where + " joins head '" + heads[actuator.head].name +
                     "' to itself");
    }
    if (!std::isfinite(actuator.rotation_rad)) {
      return problem(where + " has a non-finite rotation");
    }
    const Eigen::Vector2d axis =
        heads[actuator.head].rest_mm - AnchorRestPosition(actuator);
    if (axis.norm() < 1e-6) {
      return problem(where +
                     " has its anchor and head at the same rest position");
    }
    const double mismatch =
        std::remainder(RestAxisRotation(actuator) - actuator.rotation_rad,
                       2 * std::numbers::pi);
    if (std::abs(mismatch) > kMaxAxisMismatchRad) {
      return problem(
          where + ": rotation_deg " + Degrees(actuator.rotation_rad) +
          " points local +z " + Degrees(mismatch) +
          " deg away from the anchor-to-head direction; set "
          "rotation_deg to " +
          Degrees(RestAxisRotation(actuator)) + " or move the anchor");
    }
    const int a = fixed ? ground : actuator.anchor.index;
    parent[Root(parent, a)] = Root(parent, actuator.head);
  }
  for (int i = 0; i < NumHeads(); ++i) {
    if (Root(parent, i) != Root(parent, ground)) {
      return MechanismProblem{"head '" + heads[i].name +
                                  "' is not connected to any fixed anchor, "
                                  "so its position is undetermined",
                              -1, i};
    }
  }
  return std::nullopt;
}

}  // namespace softbench
