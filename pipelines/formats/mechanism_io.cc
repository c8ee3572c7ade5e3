#include "pipelines/formats/mechanism_io.h"

#include <filesystem>
#include <functional>
#include <map>
#include <set>

#include "model/units.h"
#include "pipelines/formats/builtin_mechanisms.h"
#include "util/input_error.h"
#include "util/text_file.h"
#include "util/yaml_reader.h"

namespace softbench {

// A mechanism of a hundred actuators is a few kilobytes.
constexpr int64_t kMaxMechanismBytes = int64_t{1} << 20;

namespace {

// Heads and fixed anchors share one namespace, so an actuator's `anchor`
// can name either.
enum class Kind { kHead, kFixed };
using Names = std::map<std::string, std::pair<Kind, int>>;

void AddName(const YamlReader& reader, const YAML::Node& node,
             const std::string& name, Kind kind, int index, Names* names) {
  if (!names->emplace(name, std::make_pair(kind, index)).second) {
    reader.Fail(node, "name", "'" + name + "' is used twice; rename one");
  }
}

// The heads and fixed anchors, their names into `names`.
void ParseHeadsAndAnchors(const YamlReader& reader, const YAML::Node& root,
                          Mechanism* mechanism_ptr, Names* names) {
  Mechanism& mechanism = *mechanism_ptr;
  const auto add_name = [&](const YAML::Node& node, const std::string& name,
                            Kind kind, int index) {
    AddName(reader, node, name, kind, index, names);
  };
  const YAML::Node heads = reader.Require(root, "heads");
  if (!heads.IsSequence() || heads.size() == 0) {
    reader.Fail(heads, "heads", "must be a non-empty list");
  }
  for (const YAML::Node& node : heads) {
    reader.CheckKeys(node, "heads entry", {"name", "rest_mm"});
    const auto rest = reader.Pair(reader.Require(node, "rest_mm"), "rest_mm");
    Head head{reader.String(reader.Require(node, "name"), "name"),
              {rest[0], rest[1]}};
    add_name(node, head.name, Kind::kHead, mechanism.NumHeads());
    mechanism.heads.push_back(std::move(head));
  }

  if (const YAML::Node anchors = root["anchors"]) {
    if (!anchors.IsSequence())
      reader.Fail(anchors, "anchors", "must be a list");
    for (const YAML::Node& node : anchors) {
      reader.CheckKeys(node, "anchors entry", {"name", "position_mm"});
      const auto position =
          reader.Pair(reader.Require(node, "position_mm"), "position_mm");
      FixedAnchor anchor{reader.String(reader.Require(node, "name"), "name"),
                         {position[0], position[1]}};
      add_name(node, anchor.name, Kind::kFixed,
               static_cast<int>(mechanism.fixed_anchors.size()));
      mechanism.fixed_anchors.push_back(std::move(anchor));
    }
  }
}

Actuator ParseActuator(const YamlReader& reader, const YAML::Node& node,
                       const Names& names) {
  reader.CheckKeys(node, "actuators entry",
                   {"name", "rotation_deg", "anchor", "head"});
  Actuator actuator;
  actuator.name = reader.String(reader.Require(node, "name"), "name");
  actuator.rotation_rad = DegToRad(
      reader.Number(reader.Require(node, "rotation_deg"), "rotation_deg"));
  const YAML::Node anchor_node = reader.Require(node, "anchor");
  const auto anchor = names.find(reader.String(anchor_node, "anchor"));
  if (anchor == names.end()) {
    reader.Fail(anchor_node, "anchor",
                "'" + anchor_node.Scalar() +
                    "' is neither a head nor an anchor of this file");
  }
  actuator.anchor = {anchor->second.first == Kind::kHead
                         ? AnchorRef::Kind::kHead
                         : AnchorRef::Kind::kFixed,
                     anchor->second.second};
  const YAML::Node head_node = reader.Require(node, "head");
  const auto head = names.find(reader.String(head_node, "head"));
  if (head == names.end() || head->second.first != Kind::kHead) {
    reader.Fail(head_node, "head",
                "'" + head_node.Scalar() + "' is not a head of this file");
  }
  actuator.head = head->second.second;
  return actuator;
}

}  // namespace

Mechanism ParseMechanismYaml(std::string_view yaml, const std::string& source) {
  const YamlReader reader(source);
  const YAML::Node root = reader.Parse(yaml);
  if (!root.IsMap()) {
    throw InputError(source +
                     ": a mechanism file is a map with name, heads, anchors "
                     "and actuators");
  }
  reader.CheckKeys(root, "mechanism file",
                   {"name", "description", "heads", "anchors", "actuators"});
  Mechanism mechanism;
  mechanism.name = reader.String(reader.Require(root, "name"), "name");
  Names names;
  ParseHeadsAndAnchors(reader, root, &mechanism, &names);
  const YAML::Node actuators = reader.Require(root, "actuators");
  if (!actuators.IsSequence() || actuators.size() == 0) {
    reader.Fail(actuators, "actuators", "must be a non-empty list");
  }
  std::set<std::string, std::less<>> actuator_names;
  for (const YAML::Node& node : actuators) {
    mechanism.actuators.push_back(ParseActuator(reader, node, names));
    // Pressure columns and reports name actuators, so each name is one.
    if (!actuator_names.insert(mechanism.actuators.back().name).second) {
      reader.Fail(node["name"], "name",
                  "actuator '" + mechanism.actuators.back().name +
                      "' is named twice; rename one");
    }
  }
  if (const std::optional<MechanismProblem> problem = mechanism.Problem()) {
    // Point at the entry at fault where there is one.
    const YAML::Node& at = problem->actuator >= 0 ? actuators[problem->actuator]
                           : problem->head >= 0   ? root["heads"][problem->head]
                                                  : root;
    throw InputError(reader.Where(at) + problem->message);
  }
  return mechanism;
}

std::vector<std::string> BuiltinMechanismNames() {
  std::vector<std::string> names;
  for (const BuiltinMechanism& builtin : BuiltinMechanisms()) {
    names.emplace_back(builtin.name);
  }
  return names;
}

Mechanism LoadMechanism(const std::string& name_or_path) {
  std::string names;
  for (const BuiltinMechanism& builtin : BuiltinMechanisms()) {
    if (builtin.name == name_or_path) {
      return ParseMechanismYaml(
          builtin.yaml, "built-in " + std::string(builtin.name) + ".yaml");
    }
    names += "'" + std::string(builtin.name) + "', ";
  }
  // The error_code form: a name the file system refuses (too long, say) is
  // the same user error as a missing file, not an exception of its own.
  std::error_code error;
  // Something that exists but is no regular file (a folder, a device) is
  // named for what it is by ReadTextFile's check.
  if (!std::filesystem::exists(name_or_path, error)) {
    throw InputError("mechanism '" + name_or_path +
                     "': no such mechanism; give " + names +
                     "or the path of a mechanism YAML file");
  }
  return ParseMechanismYaml(
      ReadTextFile(name_or_path, "mechanism file", kMaxMechanismBytes),
      name_or_path);
}

}  // namespace softbench
