#include "util/yaml_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>

#include "util/csv.h"
#include "util/input_error.h"

namespace softbench {

YAML::Node YamlReader::Parse(std::string_view text) const {
  try {
    return YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    throw InputError(source_ + ":" + std::to_string(e.mark.line + 1) +
                     ": not valid YAML (" + e.msg + ")");
  }
}

std::string YamlReader::Where(const YAML::Node& node) const {
  const YAML::Mark mark = node.Mark();
  if (mark.line < 0) return source_ + ": ";
  return source_ + ":" + std::to_string(mark.line + 1) + ": ";
}

void YamlReader::Fail(const YAML::Node& node, std::string_view field,
                      std::string_view message) const {
  throw InputError(Where(node) + std::string(field) + ": " +
                   std::string(message));
}

void YamlReader::CheckKeys(
    const YAML::Node& map, std::string_view field,
    std::initializer_list<std::string_view> allowed) const {
  if (!map.IsMap()) Fail(map, field, "must be a map of key: value");
  std::string list;
  for (std::string_view name : allowed) {
    list += (list.empty() ? "" : ", ") + std::string(name);
  }
  std::set<std::string, std::less<>> seen;
  for (const auto& entry : map) {
    if (!entry.first.IsScalar()) {
      Fail(entry.first, field,
           "keys must be plain names; expected one of " + list);
    }
    const std::string& key = entry.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      Fail(entry.first, key, "unknown key; expected one of " + list);
    }
    if (!seen.insert(key).second) {
      Fail(entry.first, key, "given twice; keep one");
    }
  }
}

YAML::Node YamlReader::Require(const YAML::Node& map,
                               std::string_view key) const {
  YAML::Node value = map[std::string(key)];
  if (!value) Fail(map, key, "missing; add it");
  return value;
}

YAML::Node YamlReader::RequireMap(const YAML::Node& map,
                                  std::string_view key) const {
  YAML::Node value = Require(map, key);
  if (!value.IsMap()) Fail(value, key, "must be a map of key: value");
  return value;
}

double YamlReader::Number(const YAML::Node& node,
                          std::string_view field) const {
  if (!node.IsScalar()) Fail(node, field, "must be a number");
  const std::optional<double> value = ParseDouble(node.Scalar());
  if (!value || !std::isfinite(*value)) {
    Fail(node, field, "'" + node.Scalar() + "' is not a finite number");
  }
  return *value;
}

std::string YamlReader::String(const YAML::Node& node,
                               std::string_view field) const {
  if (!node.IsScalar() || node.Scalar().empty()) {
    Fail(node, field, "must be a non-empty name");
  }
  const std::string& text = node.Scalar();
  const auto control = std::find_if(text.begin(), text.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7F;
  });
  if (control != text.end()) {
    Fail(node, field,
         fmt::format("'{}' holds control character 0x{:02X}; use printable "
                     "text on one line",
                     text.substr(0, control - text.begin()),
                     static_cast<unsigned char>(*control)));
  }
  return text;
}

bool YamlReader::Bool(const YAML::Node& node, std::string_view field) const {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value)) {
    Fail(node, field, "must be true or false");
  }
  return value;
}

std::array<double, 2> YamlReader::Pair(const YAML::Node& node,
                                       std::string_view field) const {
  if (!node.IsSequence() || node.size() != 2) {
    Fail(node, field, "must be a pair [y, z] in millimetres");
  }
  return {Number(node[0], field), Number(node[1], field)};
}

}  // namespace softbench
