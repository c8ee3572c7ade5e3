#ifndef SOFTBENCH_MODEL_UNITS_H_
#define SOFTBENCH_MODEL_UNITS_H_

#include <numbers>

namespace softbench {

// The model works in millimetres, newtons, MPa (= N/mm^2) and radians.
// Conversions of pressure units into MPa (model.md: 1 psi = 6.894757 kPa).
inline constexpr double kMpaPerPsi = 0.006894757;
inline constexpr double kMpaPerKpa = 0.001;

inline constexpr double DegToRad(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}
inline constexpr double RadToDeg(double radians) {
  return radians * 180.0 / std::numbers::pi;
}

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_UNITS_H_
