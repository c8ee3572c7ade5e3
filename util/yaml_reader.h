#ifndef SOFTBENCH_UTIL_YAML_READER_H_
#define SOFTBENCH_UTIL_YAML_READER_H_

#include <yaml-cpp/yaml.h>

#include <array>
#include <initializer_list>
#include <string>
#include <string_view>

namespace softbench {

// Reading values from YAML (yaml-cpp) with errors that name the source, line
// and field: every failure throws InputError("source:line: field: what to
// change").
class YamlReader {
 public:
  explicit YamlReader(std::string source) : source_(std::move(source)) {}

  // Parses a document; a syntax error becomes an InputError with its line.
  YAML::Node Parse(std::string_view text) const;

  // "source:line: " for `node` (line of the node, 1-based).
  std::string Where(const YAML::Node& node) const;
  [[noreturn]] void Fail(const YAML::Node& node, std::string_view field,
                         std::string_view message) const;

  // Checks that `map` (the value of `field`) is a map whose keys are plain
  // names, each given once and each one of `allowed` (catches typos). Every
  // map is checked this way before its keys are read, so a list or a number
  // where a map belongs is a located error, never yaml-cpp's.
  void CheckKeys(const YAML::Node& map, std::string_view field,
                 std::initializer_list<std::string_view> allowed) const;
  YAML::Node Require(const YAML::Node& map, std::string_view key) const;
  // A required map of the given name.
  YAML::Node RequireMap(const YAML::Node& map, std::string_view key) const;

  double Number(const YAML::Node& node, std::string_view field) const;
  // A non-empty single-line name without control characters.
  std::string String(const YAML::Node& node, std::string_view field) const;
  // true or false (YAML's spellings).
  bool Bool(const YAML::Node& node, std::string_view field) const;
  // A [y, z] pair of numbers.
  std::array<double, 2> Pair(const YAML::Node& node,
                             std::string_view field) const;

 private:
  std::string source_;
};

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_YAML_READER_H_
