#ifndef SOFTBENCH_MODEL_UNITS_H_
#define SOFTBENCH_MODEL_UNITS_H_

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "util/join_names.h"

namespace softbench {

// The model works in millimetres, newtons, MPa (= N/mm^2) and radians.
// Conversions of pressure units into MPa (model.md: 1 psi = 6.894757 kPa).
inline constexpr double kMpaPerPsi = 0.006894757;
inline constexpr double kMpaPerKpa = 0.001;
inline constexpr double kMpaPerBar = 0.1;

// The pressure units files and options may state, by the names they use: the
// one list every parser, help text and message uses. A pressure is never
// assumed to be in one of them. Names are read in any case ("kPa", "PSI").
struct PressureUnit {
  std::string_view name;
  double mpa_per_unit;
};
inline constexpr PressureUnit kPressureUnits[] = {{"psi", kMpaPerPsi},
                                                  {"kpa", kMpaPerKpa},
                                                  {"mpa", 1.0},
                                                  {"bar", kMpaPerBar}};

// The unit `name` names, in any case ("kPa" is kpa); nullptr if none.
inline const PressureUnit* FindPressureUnit(std::string_view name) {
  for (const PressureUnit& unit : kPressureUnits) {
    if (unit.name.size() == name.size() &&
        std::equal(name.begin(), name.end(), unit.name.begin(),
                   [](char a, char b) {
                     return (a >= 'A' && a <= 'Z' ? a - 'A' + 'a' : a) == b;
                   })) {
      return &unit;
    }
  }
  return nullptr;
}

// MPa per unit of `name` (in any case); nullopt for an unknown name.
inline std::optional<double> MpaPerPressureUnit(std::string_view name) {
  if (const PressureUnit* unit = FindPressureUnit(name)) {
    return unit->mpa_per_unit;
  }
  return std::nullopt;
}

// "psi, kpa, mpa or bar", for help texts and errors.
inline std::string PressureUnitNames() {
  std::vector<std::string_view> names;
  for (const PressureUnit& unit : kPressureUnits) names.push_back(unit.name);
  return JoinNames(names);
}

// No pneumatic actuator holds more than this (100 MPa is 14,500 psi, over a
// hundred times the burst pressure of a printed bellows): a pressure above it
// is a typo or a wrong unit, and is refused before the model turns it into
// numbers that overflow or mean nothing.
inline constexpr double kMaxPlausiblePressureMpa = 100.0;

// Why `value`, in a unit of `mpa_per_unit` MPa named `unit`, is not a gauge
// pressure a bench can hold (not finite, negative, or above
// kMaxPlausiblePressureMpa), or nothing when it is one.
inline std::optional<std::string> ImplausiblePressure(double value,
                                                      double mpa_per_unit,
                                                      std::string_view unit) {
  std::ostringstream why;
  why << value << " " << unit;
  if (!std::isfinite(value)) return "'" + why.str() + "' is not a number";
  if (value < 0.0) {
    return why.str() + " is negative; pressures are gauge pressures >= 0";
  }
  if (value * mpa_per_unit > kMaxPlausiblePressureMpa) {
    why << " is above " << kMaxPlausiblePressureMpa
        << " MPa, more than any pneumatic actuator holds; check the value "
           "and its unit";
    return why.str();
  }
  return std::nullopt;
}

inline constexpr double DegToRad(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}
inline constexpr double RadToDeg(double radians) {
  return radians * 180.0 / std::numbers::pi;
}

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_UNITS_H_
