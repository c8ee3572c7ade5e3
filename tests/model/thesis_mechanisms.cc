#include "tests/model/thesis_mechanisms.h"

#include <cmath>

#include "model/units.h"

namespace softbench::testing {
namespace {

Actuator MakeActuator(const std::string& name, double rotation_deg,
                      AnchorRef::Kind kind, int anchor, int head) {
  return {name, DegToRad(rotation_deg), {kind, anchor}, head};
}

}  // namespace

Mechanism DeltaMechanism() {
  constexpr double kD = 27.0;
  Mechanism m;
  m.name = "delta";
  m.heads = {{"head", {0.0, 0.0}}};
  const double phis[] = {0.0, 120.0, -120.0};
  for (int i = 0; i < 3; ++i) {
    // Anchor i at -D * R_i * (0, 1).
    const Eigen::Vector2d anchor = -kD * RotationX(DegToRad(phis[i])).col(1);
    m.fixed_anchors.push_back({"ring" + std::to_string(i + 1), anchor});
    m.actuators.push_back(MakeActuator(std::to_string(i + 1), phis[i],
                                       AnchorRef::Kind::kFixed, i, 0));
  }
  return m;
}

Mechanism FloatingMechanism() {
  constexpr double kY = 26.98, kZ = 15.58, kA0 = 39.70;
  Mechanism m;
  m.name = "floating";
  m.heads = {{"left", {0.0, 0.0}}, {"right", {0.0, kA0}}};
  m.fixed_anchors = {{"ring1", {-kY, -kZ}},
                     {"ring2", {kY, -kZ}},
                     {"ring3", {kY, kZ + kA0}},
                     {"ring4", {-kY, kZ + kA0}}};
  const auto fixed = AnchorRef::Kind::kFixed;
  m.actuators = {
      MakeActuator("1", -60, fixed, 0, 0), MakeActuator("2", 60, fixed, 1, 0),
      MakeActuator("3", 120, fixed, 2, 1), MakeActuator("4", -120, fixed, 3, 1),
      MakeActuator("5", 0, AnchorRef::Kind::kHead, 0, 1)};
  return m;
}

Mechanism ThreeHeadChain() {
  Mechanism m;
  m.name = "chain";
  m.heads = {{"h1", {0.0, 30.0}}, {"h2", {0.0, 60.0}}, {"h3", {0.0, 90.0}}};
  m.fixed_anchors = {{"bottom", {0.0, 0.0}},
                     {"top", {0.0, 120.0}},
                     {"side1", {-30.0, 30.0}},
                     {"side2", {30.0, 60.0}},
                     {"side3", {-30.0, 90.0}}};
  const auto fixed = AnchorRef::Kind::kFixed;
  const auto head = AnchorRef::Kind::kHead;
  m.actuators = {MakeActuator("bottom", 0, fixed, 0, 0),
                 MakeActuator("h1-h2", 0, head, 0, 1),
                 MakeActuator("h2-h3", 0, head, 1, 2),
                 MakeActuator("top", 180, fixed, 1, 2),
                 MakeActuator("side1", -90, fixed, 2, 0),
                 MakeActuator("side2", 90, fixed, 3, 1),
                 MakeActuator("side3", -90, fixed, 4, 2)};
  return m;
}

}  // namespace softbench::testing
