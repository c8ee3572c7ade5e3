#ifndef SOFTBENCH_TESTS_MODEL_THESIS_MECHANISMS_H_
#define SOFTBENCH_TESTS_MODEL_THESIS_MECHANISMS_H_

#include "model/mechanism.h"

namespace softbench::testing {

// The thesis's mechanisms built in code from shared/spec/model.md, so tests of
// the model do not depend on the YAML files (which are checked against these).
Mechanism DeltaMechanism();     // D = 27.0 mm, phi = 0, +120, -120 deg
Mechanism FloatingMechanism();  // Y = 26.98, Z = 15.58, a0 = 39.70 mm

// A user-written network not in the thesis: three heads in series between two
// fixed anchors, each head also pulled sideways by one actuator. Seven
// actuators, six unknowns.
Mechanism ThreeHeadChain();

}  // namespace softbench::testing

#endif  // SOFTBENCH_TESTS_MODEL_THESIS_MECHANISMS_H_
