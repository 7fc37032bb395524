// Case-file reader: parse the YAML, apply --set overrides, then walk the tree with a CaseReader
// that knows each node's key path, so every check reports "<where>: <key.path>: <problem>".
#include "solver/io/case_reader.hpp"

#include "solver/core/error.hpp"
#include "solver/io/case_node.hpp"
#include "solver/io/material_library.hpp"
#include "solver/material/material.hpp"
#include "solver/scenes/scene.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string_view>
#include <utility>

namespace sphfem {
namespace {

using Names = std::vector<std::string_view>;

std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

// True if `path` is `prefix` or lies below it: "a.b.c" is under "a.b", "a.bc" is not.
bool is_under(const std::string& path, const std::string& prefix) {
  return path.starts_with(prefix) && (path.size() == prefix.size() || path[prefix.size()] == '.');
}

std::string comma_list(const Names& names) {
  std::string out;
  for (const std::string_view name : names)
    out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

// Letters, digits, '_' and any of `extra`.
bool is_name(const std::string& text, std::string_view extra) {
  return !text.empty() && std::ranges::all_of(text, [extra](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' ||
           extra.find(c) != std::string_view::npos;
  });
}

std::string line_of(const YAML::Mark& mark) {
  return std::to_string(std::max(mark.line, 0) + 1);
}

// How a node reads in a message: a scalar as written (quoted if it was), else its kind.
std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
  case YAML::NodeType::Scalar:
    return node.Tag() == "!" ? '"' + node.Scalar() + '"' : node.Scalar();
  case YAML::NodeType::Sequence:
    return "a list of " + std::to_string(node.size());
  case YAML::NodeType::Map:
    return "a map";
  default:
    return "null";
  }
}

std::string format(const Vec3& v) {
  std::ostringstream out;
  out << '[' << v.x() << ", " << v.y() << ", " << v.z() << ']';
  return out.str();
}

std::string geometry_name(GeometrySpec::Kind kind) {
  switch (kind) {
  case GeometrySpec::Kind::Box:
    return "box";
  case GeometrySpec::Kind::Cylinder:
    return "cylinder";
  case GeometrySpec::Kind::File:
    return "geometry file";
  case GeometrySpec::Kind::Ring:
    return "ring";
  }
  return "geometry";
}

Names face_names(const GeometrySpec& g) {
  switch (g.kind) {
  case GeometrySpec::Kind::Box:
    return {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  case GeometrySpec::Kind::Cylinder:
    if (g.cylinder.sector == Sector::Quarter)
      return {"base", "top", "side", "xmin", "ymin"};
    if (g.cylinder.sector == Sector::Half)
      return {"base", "top", "side", "ymin"};
    return {"base", "top", "side"};
  case GeometrySpec::Kind::Ring:
    if (g.ring.sector == Sector::Quarter)
      return {"inner", "rim", "bottom", "top", "xmin", "ymin"};
    if (g.ring.sector == Sector::Half)
      return {"inner", "rim", "bottom", "top", "ymin"};
    return {"inner", "rim", "bottom", "top"};
  case GeometrySpec::Kind::File:
    break;
  }
  return {};
}

// Geometry files gmsh reads as solids: its own script format and OpenCASCADE's exchange formats.
const Names geometry_file_types{".geo", ".step", ".stp", ".brep"};

constexpr auto positive = [](double v) { return v > 0; };
constexpr auto non_negative = [](double v) { return v >= 0; };

// ---- Overrides ---------------------------------------------------------------------------

[[noreturn]] void bad_override(const std::string& text, const std::string& what) {
  throw Error("--set " + text + ": " + what);
}

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> keys;
  std::istringstream in(path);
  for (std::string key; std::getline(in, key, '.');)
    keys.push_back(key);
  if (path.empty() || path.back() == '.')
    keys.emplace_back();
  return keys;
}

// How many places in `tree` hold `target`: more than one if YAML aliases share it. `above`
// holds the ancestors of `tree`, so that an alias to an ancestor is not followed.
int holders(const YAML::Node& tree, const YAML::Node& target, std::vector<YAML::Node>& above) {
  if (tree.is(target))
    return 1;
  if (std::ranges::any_of(above, [&tree](const YAML::Node& node) { return node.is(tree); }))
    return 0;
  above.push_back(tree);
  int count = 0;
  if (tree.IsMap())
    for (const auto& pair : tree)
      count += holders(pair.second, target, above);
  if (tree.IsSequence())
    for (const YAML::Node& item : tree)
      count += holders(item, target, above);
  above.pop_back();
  return count;
}

// `slot`, unless YAML aliases share it (then overriding it would change them too).
YAML::Node unshared(const YAML::Node& root, const YAML::Node& slot, const std::string& path,
                    const std::string& text) {
  std::vector<YAML::Node> above;
  if (slot.IsDefined() && holders(root, slot, above) > 1)
    bad_override(text, path + " is shared with other keys through a YAML alias");
  return slot;
}

// The child of `node` at `key` for an override: a list element by index, or a map entry (added,
// still undefined, if absent). Extends `path` with the key. Assigning to it writes into the node
// in place, so the child must not be one that YAML aliases share elsewhere in `root`.
YAML::Node override_slot(const YAML::Node& root, YAML::Node& node, const std::string& key,
                         std::string& path, const std::string& text) {
  const std::string here = path.empty() ? "the top level" : path;
  if (node.IsSequence()) {
    std::size_t index = 0;
    const char* end = key.data() + key.size();
    if (const auto [stop, error] = std::from_chars(key.data(), end, index);
        error != std::errc{} || stop != end)
      bad_override(text, here + " is a list, so '" + key + "' must be an index");
    if (index >= node.size())
      bad_override(text, "index " + key + " out of range (" + here + " has " +
                             std::to_string(node.size()) + " entries)");
    path = join(path, std::to_string(index));
    return unshared(root, node[index], path, text);
  }
  if (!node.IsMap() && !node.IsNull())
    bad_override(text, here + " is a single value (" + describe(node) + "), not a map or a list");
  path = join(path, key);
  return unshared(root, node[key], path, text);
}

// Every scalar of the tree by its key path, list entries by index (Case::keys).
void flatten(const YAML::Node& node, const std::string& path,
             std::map<std::string, std::string>& out) {
  if (node.IsMap()) {
    for (const auto& entry : node)
      flatten(entry.second, join(path, entry.first.as<std::string>()), out);
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      flatten(node[i], join(path, std::to_string(i)), out);
  } else {
    out[path] = node.IsScalar() ? node.Scalar() : "";
  }
}

// Applies one "key.path=value" override to the tree in place; returns its key path.
std::string apply_override(YAML::Node& root, const std::string& text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos)
    bad_override(text, "expected key.path=value");
  const std::vector<std::string> keys = split_path(text.substr(0, equals));
  if (std::ranges::any_of(keys, &std::string::empty))
    bad_override(text, "empty key in the key path");
  YAML::Node value;
  try {
    value = YAML::Load(text.substr(equals + 1));
  } catch (const YAML::ParserException& e) {
    bad_override(text, "YAML syntax error in the value: " + e.msg);
  }
  YAML::Node node = root;
  std::string path;
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    YAML::Node next = override_slot(root, node, keys[i], path, text);
    if (!next.IsDefined())
      next = YAML::Node(YAML::NodeType::Map);
    node.reset(next);
  }
  override_slot(root, node, keys.back(), path, text) = value;
  return path;
}

// ---- Validation --------------------------------------------------------------------------

// A node and its key path ("bodies.bar.geometry"; list entries by index, "probes.0").
struct Located {
  YAML::Node node;
  std::string path;
};

// The two bodies of a list item (attach, contact) as given, and the item.
struct BodyPair {
  std::array<std::string, 2> names;
  Located item;
};

// A map entry; key and value are both located at the entry's path.
struct Entry {
  std::string name;
  Located key, value;
};

} // namespace

class CaseReader {
public:
  // `folder`: where relative geometry file paths start (the case file's folder).
  CaseReader(std::string file, std::filesystem::path folder, std::vector<std::string> overrides)
      : file_(std::move(file)), folder_(std::move(folder)), overrides_(std::move(overrides)) {}

  Case read(const YAML::Node& root) const;
  std::vector<MaterialSpec> read_materials(const YAML::Node& root) const;

private:
  friend class CaseNode; // a scene's view of one block, with these checks

  std::string file_;
  std::filesystem::path folder_;
  std::vector<std::string> overrides_; // key paths set by --set, in the order applied

  // "--set <path>" if the last override covering the node supplied or created it, else
  // "<file>:<line>".
  std::string where(const Located& at) const {
    const auto covers = [&at](const std::string& set) { return is_under(at.path, set); };
    const auto created = [&at](const std::string& set) { return is_under(set, at.path); };
    for (auto set = overrides_.rbegin(); set != overrides_.rend(); ++set)
      if (covers(*set) || (at.node.Mark().is_null() && created(*set)))
        return "--set " + *set;
    return file_ + ":" + line_of(at.node.Mark());
  }

  // Reports `what` at `at`'s location, under the key path `path`.
  [[noreturn]] void fail(const Located& at, const std::string& path,
                         const std::string& what) const {
    throw Error(where(at) + ": " + (path.empty() ? "(top level)" : path) + ": " + what);
  }
  [[noreturn]] void fail(const Located& at, const std::string& what) const {
    fail(at, at.path, what);
  }

  // Structure.
  std::vector<Entry> entries(const Located& map) const;
  void check_map(const Located& map, const Names& allowed) const;
  std::vector<Entry> named_entries(const Located& map, std::string_view what) const;
  std::vector<Located> items(const Located& list) const;
  Located child(const Located& map, const std::string& key) const;
  Located required(const Located& map, const std::string& key, std::string_view meaning) const;

  // Values.
  double number(const Located& at) const;
  template <class Ok> double number(const Located& at, std::string_view rule, Ok ok) const;
  template <class Ok>
  double number_or(const Located& map, const std::string& key, double fallback,
                   std::string_view rule, Ok ok) const;
  bool flag(const Located& at) const;
  bool term(const Located& at, const Names& parameters) const;
  std::string text(const Located& at) const;
  std::string one_of(const Located& at, const Names& names, std::string_view what) const;
  template <class T>
  T choice(const Located& at, std::string_view what,
           std::initializer_list<std::pair<std::string_view, T>> options) const;
  Vec3 vec3(const Located& at) const;
  TimeFunction time_function(const Located& at) const;

  // Sections.
  TimeSpec time(const Located& at) const;
  MaterialSpec material(const Entry& entry) const;
  JohnsonCook johnson_cook(const Located& at) const;
  RateForm rate_form(const Located& at) const;
  DuctileDamage damage(const Located& at, RateForm strength_form) const;
  AdiabaticHeating heating(const Located& at) const;
  MieGruneisen mie_gruneisen(const Located& at) const;
  BodySpec body(const Entry& entry, const std::vector<MaterialSpec>& materials) const;
  GeometrySpec geometry(const Located& at, Method method) const;
  Sector sector(const Located& shape, Method method) const;
  RingGeometry ring(const Located& at) const;
  std::filesystem::path geometry_file(const Located& at) const;
  const BodySpec& body_ref(const Located& item, const std::vector<BodySpec>& bodies) const;
  void check_particle_faces(const Located& at, const BodySpec& body) const;
  BoundaryConditionSpec boundary_condition(const Located& at, const Case& c) const;
  PressureLoadSpec load(const Located& at, const Case& c) const;
  std::vector<ProbeSpec> probes(const Located& at, const Case& c) const;
  std::array<const BodySpec*, 2> body_pair(const Located& item, const Case& c,
                                           std::vector<BodyPair>& earlier) const;
  std::vector<AttachSpec> attachments(const Located& at, const Case& c) const;
  ContactSpec contact_law(const Located& at, const MaterialSpec& a, const MaterialSpec& b) const;
  std::vector<ContactSpec> contacts(const Located& at, const Case& c) const;
  FemSpec fem(const Located& at) const;
  SphSpec sph(const Located& at) const;
  OutputSpec output(const Located& at) const;
  Case common(const Located& root) const;
  void options(const Located& root, Case& c) const;
  Case scene(const Located& root, const Located& name) const;
};

// The entries of a map in file order; keys must be single values and appear once.
std::vector<Entry> CaseReader::entries(const Located& map) const {
  if (!map.node.IsMap())
    fail(map, "must be a map, got " + describe(map.node));
  std::vector<Entry> out;
  for (const auto& pair : map.node) {
    if (!pair.first.IsScalar())
      fail(map, "keys must be names, got " + describe(pair.first));
    const std::string name = pair.first.Scalar();
    const Entry entry{
        name, {pair.first, join(map.path, name)}, {pair.second, join(map.path, name)}};
    if (const auto first = std::ranges::find(out, name, &Entry::name); first != out.end())
      fail(entry.key, "duplicate key (first given at " + where(first->key) + ")");
    out.push_back(entry);
  }
  return out;
}

// A closed map: only the `allowed` keys.
void CaseReader::check_map(const Located& map, const Names& allowed) const {
  for (const Entry& entry : entries(map))
    if (std::ranges::find(allowed, entry.name) == allowed.end())
      fail(entry.key, "unknown key (expected one of: " + comma_list(allowed) + ")");
}

// A map from user-chosen names (materials, bodies) to definitions; at least one.
std::vector<Entry> CaseReader::named_entries(const Located& map, std::string_view what) const {
  std::vector<Entry> out = entries(map);
  if (out.empty())
    fail(map, "must define at least one " + std::string(what));
  for (const Entry& entry : out)
    if (!is_name(entry.name, ""))
      fail(entry.key, "invalid " + std::string(what) + " name (use letters, digits and _)");
  return out;
}

std::vector<Located> CaseReader::items(const Located& list) const {
  if (!list.node.IsSequence())
    fail(list, "must be a list, got " + describe(list.node));
  std::vector<Located> out;
  for (const YAML::Node& item : list.node)
    out.push_back({item, join(list.path, std::to_string(out.size()))});
  return out;
}

// The value at `key` in a map already checked by check_map(); undefined when absent.
Located CaseReader::child(const Located& map, const std::string& key) const {
  return {std::as_const(map.node)[key], join(map.path, key)};
}

Located CaseReader::required(const Located& map, const std::string& key,
                             std::string_view meaning) const {
  Located at = child(map, key);
  if (!at.node.IsDefined())
    fail(map, at.path, "missing key (" + std::string(meaning) + ")");
  return at;
}

double CaseReader::number(const Located& at) const {
  double value = 0;
  if (!at.node.IsScalar() || at.node.Tag() == "!" || !YAML::convert<double>::decode(at.node, value))
    fail(at, "must be a number, got " + describe(at.node));
  if (!std::isfinite(value))
    fail(at, "must be a finite number, got " + describe(at.node));
  return value;
}

// A number satisfying `ok`; `rule` says how, for the message ("> 0 kg/m³").
template <class Ok>
double CaseReader::number(const Located& at, std::string_view rule, Ok ok) const {
  const double value = number(at);
  if (!ok(value))
    fail(at, "must be " + std::string(rule) + ", got " + describe(at.node));
  return value;
}

template <class Ok>
double CaseReader::number_or(const Located& map, const std::string& key, double fallback,
                             std::string_view rule, Ok ok) const {
  const Located at = child(map, key);
  return at.node.IsDefined() ? number(at, rule, ok) : fallback;
}

bool CaseReader::flag(const Located& at) const {
  bool value = false;
  if (!at.node.IsScalar() || at.node.Tag() == "!" || !YAML::convert<bool>::decode(at.node, value))
    fail(at, "must be true or false, got " + describe(at.node));
  return value;
}

// A physics term: false (off), true (on with default parameters) or a map of some of its
// `parameters` (on; the caller reads them). Returns whether the term is on.
bool CaseReader::term(const Located& at, const Names& parameters) const {
  if (at.node.IsMap()) {
    check_map(at, parameters);
    return true;
  }
  bool on = false;
  if (!at.node.IsScalar() || at.node.Tag() == "!" || !YAML::convert<bool>::decode(at.node, on))
    fail(at, "must be false, true or a map of " + comma_list(parameters) + ", got " +
                 describe(at.node));
  return on;
}

std::string CaseReader::text(const Located& at) const {
  if (!at.node.IsScalar())
    fail(at, "must be a string, got " + describe(at.node));
  return at.node.Scalar();
}

std::string CaseReader::one_of(const Located& at, const Names& names, std::string_view what) const {
  std::string value = text(at);
  if (std::ranges::find(names, value) == names.end())
    fail(at, "unknown " + std::string(what) + " '" + value +
                 "' (expected one of: " + comma_list(names) + ")");
  return value;
}

template <class T>
T CaseReader::choice(const Located& at, std::string_view what,
                     std::initializer_list<std::pair<std::string_view, T>> options) const {
  Names names;
  for (const auto& option : options)
    names.push_back(option.first);
  const std::string value = one_of(at, names, what);
  return std::ranges::find(options, value, &std::pair<std::string_view, T>::first)->second;
}

Vec3 CaseReader::vec3(const Located& at) const {
  if (!at.node.IsSequence() || at.node.size() != 3)
    fail(at, "must be a list of 3 numbers [x, y, z], got " + describe(at.node));
  const std::vector<Located> xyz = items(at);
  return {number(xyz[0]), number(xyz[1]), number(xyz[2])};
}

// A piecewise-linear table [[t, f], ...]: at least one row, times >= 0, strictly increasing.
TimeFunction CaseReader::time_function(const Located& at) const {
  const std::vector<Located> rows = items(at);
  if (rows.empty())
    fail(at, "must have at least one row [t, f]");
  std::vector<std::pair<double, double>> table;
  std::string previous; // the previous time, as written
  for (const Located& row : rows) {
    if (!row.node.IsSequence() || row.node.size() != 2)
      fail(row, "must be a row [t, f] of 2 numbers, got " + describe(row.node));
    const std::vector<Located> cells = items(row);
    const double t = number(cells[0], ">= 0 s (negative times are not allowed)", non_negative);
    if (!table.empty() && t <= table.back().first)
      fail(cells[0], "times must be strictly increasing, got " + describe(cells[0].node) +
                         " after " + previous);
    previous = describe(cells[0].node);
    table.emplace_back(t, number(cells[1]));
  }
  return TimeFunction(std::move(table));
}

TimeSpec CaseReader::time(const Located& at) const {
  check_map(at, {"end", "cfl", "output_interval", "history_interval", "energy_limit"});
  TimeSpec spec;
  spec.end = number(required(at, "end", "end time, s"), "> 0 s", positive);
  spec.cfl = number_or(at, "cfl", spec.cfl, "in (0, 1]", [](double v) { return v > 0 && v <= 1; });
  spec.output_interval =
      number(required(at, "output_interval", "time between output frames, s"), "> 0 s", positive);
  spec.history_interval =
      number_or(at, "history_interval", spec.history_interval, ">= 0 s", non_negative);
  spec.energy_limit = number_or(at, "energy_limit", spec.energy_limit, "> 0", positive);
  return spec;
}

MaterialSpec CaseReader::material(const Entry& entry) const {
  const Located& at = entry.value;
  check_map(at, {"model", "density", "youngs_modulus", "poisson_ratio", "johnson_cook", "damage",
                 "heating", "eos", "erosion"});
  MaterialSpec spec;
  spec.name = entry.name;
  const Located model = required(at, "model", "material model: " + comma_list(material_models));
  spec.model = one_of(model, material_models, "model");
  spec.density = number(required(at, "density", "mass density, kg/m³"), "> 0 kg/m³", positive);
  spec.youngs_modulus =
      number(required(at, "youngs_modulus", "Young's modulus, Pa"), "> 0 Pa", positive);
  spec.poisson_ratio = number(required(at, "poisson_ratio", "Poisson's ratio"), "in (-1, 0.5)",
                              [](double v) { return v > -1 && v < 0.5; });
  const bool plastic = spec.model == "johnson_cook";
  if (plastic)
    spec.johnson_cook =
        johnson_cook(required(at, "johnson_cook", "the Johnson–Cook constants A, B, n, C, ..."));
  for (const char* key : {"johnson_cook", "damage", "heating"})
    if (const Located block = child(at, key); block.node.IsDefined() && !plastic)
      fail(block, std::string("needs model: johnson_cook (an elastic material has no ") +
                      (std::string_view(key) == "johnson_cook" ? "flow stress" : key) + ")");
  if (const Located block = child(at, "damage"); block.node.IsDefined())
    spec.damage = damage(block, spec.johnson_cook->rate_form);
  if (const Located block = child(at, "heating"); block.node.IsDefined())
    spec.heating = heating(block);
  if (const Located block = child(at, "eos"); block.node.IsDefined())
    spec.eos = mie_gruneisen(block);
  if (const Located erosion = child(at, "erosion"); erosion.node.IsDefined()) {
    spec.erosion = flag(erosion);
    if (spec.erosion && !spec.damage)
      fail(erosion, "needs a damage block: only failed elements are eroded");
  }
  return spec;
}

JohnsonCook CaseReader::johnson_cook(const Located& at) const {
  check_map(at, {"A", "B", "n", "C", "rate_form", "reference_strain_rate", "m",
                 "melting_temperature", "reference_temperature"});
  JohnsonCook jc;
  jc.A = number(required(at, "A", "initial yield stress, Pa"), "> 0 Pa", positive);
  jc.B = number(required(at, "B", "hardening modulus, Pa"), ">= 0 Pa", non_negative);
  jc.n = number(required(at, "n", "hardening exponent"), "> 0", positive);
  jc.C = number(required(at, "C", "strain-rate sensitivity"), ">= 0", non_negative);
  jc.rate_form = rate_form(required(at, "rate_form", "power (1 + ṙ*)^C or log 1 + C ln ṙ*"));
  jc.reference_strain_rate =
      number(required(at, "reference_strain_rate", "reference plastic strain rate ṗ0, 1/s"),
             "> 0 1/s", positive);
  jc.m = number_or(at, "m", jc.m, "> 0", positive);
  jc.reference_temperature =
      number_or(at, "reference_temperature", jc.reference_temperature, "> 0 K", positive);
  jc.melting_temperature =
      number_or(at, "melting_temperature", jc.melting_temperature, "> 0 K", positive);
  if (jc.melting_temperature <= jc.reference_temperature)
    fail(at, "melting_temperature (" + std::to_string(jc.melting_temperature) +
                 " K) must exceed reference_temperature (" +
                 std::to_string(jc.reference_temperature) + " K)");
  return jc;
}

RateForm CaseReader::rate_form(const Located& at) const {
  return choice<RateForm>(at, "rate form", {{"power", RateForm::Power}, {"log", RateForm::Log}});
}

DuctileDamage CaseReader::damage(const Located& at, RateForm strength_form) const {
  check_map(at, {"D1", "D2", "D3", "D4", "D5", "rate_form", "critical_damage", "threshold_strain",
                 "regularisation_length", "regularisation_exponent"});
  DuctileDamage d;
  d.D1 = number(required(at, "D1", "fracture strain constant"));
  d.D2 = number(required(at, "D2", "fracture strain constant"));
  d.D3 = number(required(at, "D3", "triaxiality exponent"));
  d.D4 = number(required(at, "D4", "rate sensitivity of the fracture strain"));
  d.D5 = number_or(at, "D5", d.D5, "a number", [](double) { return true; });
  d.rate_form = strength_form;
  if (const Located form = child(at, "rate_form"); form.node.IsDefined())
    d.rate_form = rate_form(form);
  d.critical_damage = number_or(at, "critical_damage", d.critical_damage, "in (0, 1]",
                                [](double v) { return v > 0 && v <= 1; });
  d.threshold_strain = number_or(at, "threshold_strain", d.threshold_strain, ">= 0", non_negative);
  d.regularisation_length =
      number_or(at, "regularisation_length", d.regularisation_length, "> 0 (m)", positive);
  d.regularisation_exponent = number_or(at, "regularisation_exponent", d.regularisation_exponent,
                                        "in (0, 2]", [](double v) { return v > 0 && v <= 2; });
  if (const Located beta = child(at, "regularisation_exponent");
      beta.node.IsDefined() && !(d.regularisation_length > 0))
    fail(beta, "scales the regularisation length's factor: give regularisation_length too");
  return d;
}

AdiabaticHeating CaseReader::heating(const Located& at) const {
  check_map(at, {"taylor_quinney", "specific_heat"});
  AdiabaticHeating h;
  h.taylor_quinney = number_or(at, "taylor_quinney", h.taylor_quinney, "in [0, 1]",
                               [](double v) { return v >= 0 && v <= 1; });
  h.specific_heat = number(required(at, "specific_heat", "specific heat C_p, J/(kg K)"),
                           "> 0 J/(kg K)", positive);
  return h;
}

MieGruneisen CaseReader::mie_gruneisen(const Located& at) const {
  check_map(at, {"model", "c0", "s", "gamma0", "a"});
  one_of(required(at, "model", "equation of state: mie_gruneisen"), {"mie_gruneisen"}, "eos");
  MieGruneisen eos;
  eos.c0 = number(required(at, "c0", "bulk sound speed, m/s"), "> 0 m/s", positive);
  eos.s = number(required(at, "s", "slope of the U_s–u_p Hugoniot"), ">= 1",
                 [](double v) { return v >= 1; });
  eos.gamma0 = number(required(at, "gamma0", "Grüneisen coefficient"), ">= 0", non_negative);
  eos.a = number_or(at, "a", eos.a, ">= 0", non_negative);
  return eos;
}

// A geometry file path, relative to the case file's folder; the file must exist. Returns the
// absolute path.
std::filesystem::path CaseReader::geometry_file(const Located& at) const {
  namespace fs = std::filesystem;
  const std::string name = text(at);
  if (name.empty())
    fail(at, "must name a geometry file, got an empty string");
  const fs::path given(name);
  const std::string type = given.extension().string();
  if (std::ranges::find(geometry_file_types, type) == geometry_file_types.end())
    fail(at, "unsupported geometry file type '" + type +
                 "' (expected one of: " + comma_list(geometry_file_types) + ")");
  const fs::path path = fs::absolute(folder_ / given).lexically_normal();
  std::error_code status;
  if (!fs::is_regular_file(path, status))
    fail(at, "geometry file '" + name + "' not found (looked for " + path.string() + ")");
  return path;
}

Sector CaseReader::sector(const Located& shape, Method method) const {
  const Located at = child(shape, "sector");
  if (!at.node.IsDefined())
    return Sector::Full;
  const Sector sector = choice<Sector>(
      at, "sector", {{"full", Sector::Full}, {"half", Sector::Half}, {"quarter", Sector::Quarter}});
  if (sector != Sector::Full && method != Method::Fem)
    fail(at,
         describe(at.node) + " is only meshed in hexahedra (method fem); an sph body takes a box");
  return sector;
}

RingGeometry CaseReader::ring(const Located& at) const {
  check_map(at, {"base", "half_width", "radius", "thickness", "rim_element_size", "sector"});
  RingGeometry g;
  g.base = vec3(required(at, "base", "centre of the bottom face [x, y, z], m"));
  g.half_width =
      number(required(at, "half_width", "half-width of the square hole, m"), "> 0 m", positive);
  const Located radius = required(at, "radius", "outer radius, m");
  g.radius = number(radius, "> 0 m", positive);
  if (g.radius <= std::numbers::sqrt2 * g.half_width)
    fail(radius, "must exceed the hole's corner distance √2 · half_width = " +
                     std::to_string(std::numbers::sqrt2 * g.half_width) + " m");
  g.thickness = number(required(at, "thickness", "thickness along +z, m"), "> 0 m", positive);
  g.rim_element_size =
      number_or(at, "rim_element_size", 0.0, ">= 0 m (0: square elements)", non_negative);
  g.sector = sector(at, Method::Fem);
  return g;
}

GeometrySpec CaseReader::geometry(const Located& at, Method method) const {
  check_map(at, {"box", "cylinder", "ring", "file"});
  const Located box = child(at, "box");
  const Located cylinder = child(at, "cylinder");
  const Located ring_at = child(at, "ring");
  const Located file = child(at, "file");
  if (box.node.IsDefined() + cylinder.node.IsDefined() + ring_at.node.IsDefined() +
          file.node.IsDefined() !=
      1)
    fail(at, "must have exactly one of: box, cylinder, ring, file");
  GeometrySpec spec;
  if (ring_at.node.IsDefined()) {
    if (method != Method::Fem)
      fail(ring_at, "a ring is only meshed in hexahedra (method fem)");
    spec.kind = GeometrySpec::Kind::Ring;
    spec.ring = ring(ring_at);
    return spec;
  }
  if (file.node.IsDefined()) {
    if (method != Method::Sph)
      fail(file, "a geometry file is only supported for sph bodies (a fem body needs a box or "
                 "a cylinder)");
    spec.kind = GeometrySpec::Kind::File;
    spec.file = geometry_file(file);
    return spec;
  }
  if (box.node.IsDefined()) {
    check_map(box, {"min", "max"});
    spec.kind = GeometrySpec::Kind::Box;
    spec.box.min = vec3(required(box, "min", "lower corner [x, y, z], m"));
    spec.box.max = vec3(required(box, "max", "upper corner [x, y, z], m"));
    if (!(spec.box.max.array() > spec.box.min.array()).all())
      fail(box, "empty geometry: max must exceed min in every component, got min " +
                    format(spec.box.min) + ", max " + format(spec.box.max));
    return spec;
  }
  check_map(cylinder, {"base", "axis", "radius", "sector"});
  spec.kind = GeometrySpec::Kind::Cylinder;
  spec.cylinder.base = vec3(required(cylinder, "base", "centre of the base [x, y, z], m"));
  const Located axis = required(cylinder, "axis", "axis from base to top [x, y, z], m");
  spec.cylinder.axis = vec3(axis);
  if (!(spec.cylinder.axis.norm() > 0))
    fail(axis, "empty geometry: the axis must have a non-zero length");
  spec.cylinder.radius =
      number(required(cylinder, "radius", "radius, m"), "> 0 m (empty geometry)", positive);
  spec.cylinder.sector = sector(cylinder, method);
  const Vec3& a = spec.cylinder.axis;
  if (spec.cylinder.sector == Sector::Quarter &&
      !(a.z() > 0 && a.head<2>().norm() <= 1e-12 * a.norm()))
    fail(axis, "a quarter cylinder needs an axis along +z, got " + format(a));
  if (spec.cylinder.sector == Sector::Half && !(std::abs(a.y()) <= 1e-12 * a.norm()))
    fail(axis, "a half cylinder needs an axis in the x–z plane (y = 0), got " + format(a));
  return spec;
}

BodySpec CaseReader::body(const Entry& entry, const std::vector<MaterialSpec>& materials) const {
  const Located& at = entry.value;
  check_map(at, {"method", "geometry", "element_size", "spacing", "h_factor", "lattice", "material",
                 "velocity"});
  BodySpec spec;
  spec.name = entry.name;
  spec.method = choice<Method>(required(at, "method", "discretisation: fem or sph"), "method",
                               {{"fem", Method::Fem}, {"sph", Method::Sph}});
  spec.geometry = geometry(required(at, "geometry", "box, cylinder or file"), spec.method);
  if (spec.method == Method::Fem) {
    for (const std::string key : {"spacing", "lattice"})
      if (const Located sph_only = child(at, key); sph_only.node.IsDefined())
        fail(sph_only, "only allowed for method sph (a fem body takes element_size)");
    spec.element_size =
        number(required(at, "element_size", "element edge length, m"), "> 0 m", positive);
    // The h of the body's background particles where it is in contact (h_factor · element_size).
    spec.h_factor = number_or(at, "h_factor", spec.h_factor, "> 0", positive);
  } else {
    if (const Located fem_only = child(at, "element_size"); fem_only.node.IsDefined())
      fail(fem_only, "only allowed for method fem (an sph body takes spacing)");
    spec.spacing = number(required(at, "spacing", "particle spacing Δp, m"), "> 0 m", positive);
    spec.h_factor = number_or(at, "h_factor", spec.h_factor, "in [1.0, 2.0]", [](double v) {
      return v >= sph_h_factor_low && v <= sph_h_factor_high;
    });
    if (const Located lattice = child(at, "lattice"); lattice.node.IsDefined()) {
      spec.lattice = choice<BodySpec::Lattice>(
          lattice, "lattice",
          {{"centred", BodySpec::Lattice::Centred}, {"nodes", BodySpec::Lattice::Nodes}});
      if (spec.lattice == BodySpec::Lattice::Nodes && spec.geometry.kind != GeometrySpec::Kind::Box)
        fail(lattice, "nodes is only allowed for a box geometry (use centred for a " +
                          geometry_name(spec.geometry.kind) + ")");
    }
  }
  Names material_names;
  for (const MaterialSpec& material : materials)
    material_names.push_back(material.name);
  spec.material =
      one_of(required(at, "material", "name of a material"), material_names, "material");
  if (const Located velocity = child(at, "velocity"); velocity.node.IsDefined())
    spec.velocity = vec3(velocity);
  return spec;
}

// The body named by `item`'s required "body" key.
const BodySpec& CaseReader::body_ref(const Located& item,
                                     const std::vector<BodySpec>& bodies) const {
  Names names;
  for (const BodySpec& body : bodies)
    names.push_back(body.name);
  const std::string name = one_of(required(item, "body", "name of a body"), names, "body");
  return *std::ranges::find(bodies, name, &BodySpec::name);
}

// Boundary conditions and loads on an SPH body act on its particle faces, which only a box has.
void CaseReader::check_particle_faces(const Located& at, const BodySpec& body) const {
  if (body.method == Method::Sph && body.geometry.kind != GeometrySpec::Kind::Box)
    fail(at, "'" + body.name + "' is an SPH body with a " + geometry_name(body.geometry.kind) +
                 ": particle faces exist only for box bodies");
}

BoundaryConditionSpec CaseReader::boundary_condition(const Located& at, const Case& c) const {
  check_map(at, {"type", "body", "face", "velocity", "function"});
  BoundaryConditionSpec spec;
  spec.type = choice<BoundaryType>(required(at, "type", "fixed, velocity or symmetry"),
                                   "boundary condition type",
                                   {{"fixed", BoundaryType::Fixed},
                                    {"velocity", BoundaryType::Velocity},
                                    {"symmetry", BoundaryType::Symmetry}});
  const BodySpec& body = body_ref(at, c.bodies);
  check_particle_faces(child(at, "body"), body);
  spec.body = body.name;
  spec.face = one_of(required(at, "face", "face name"), face_names(body.geometry), "face");
  const Located velocity = child(at, "velocity");
  const Located function = child(at, "function");
  if (spec.type != BoundaryType::Velocity) {
    for (const Located& velocity_only : {velocity, function})
      if (velocity_only.node.IsDefined())
        fail(velocity_only, "only allowed for type velocity");
    return spec;
  }
  const Located given = required(at, "velocity", "[vx, vy, vz] in m/s, ~ for a free component");
  if (!given.node.IsSequence() || given.node.size() != 3)
    fail(given, "must be a list of 3 entries [vx, vy, vz], each a number or ~, got " +
                    describe(given.node));
  const std::vector<Located> components = items(given);
  for (std::size_t i = 0; i < 3; ++i)
    if (!components[i].node.IsNull())
      spec.velocity[i] = number(components[i]);
  if (std::ranges::none_of(spec.velocity, [](const auto& v) { return v.has_value(); }))
    fail(given, "must prescribe at least one component, got [~, ~, ~]");
  if (function.node.IsDefined())
    spec.function = time_function(function);
  return spec;
}

PressureLoadSpec CaseReader::load(const Located& at, const Case& c) const {
  check_map(at, {"type", "body", "face", "pressure", "function"});
  one_of(required(at, "type", "load type: pressure"), {"pressure"}, "load type");
  PressureLoadSpec spec;
  const BodySpec& body = body_ref(at, c.bodies);
  check_particle_faces(child(at, "body"), body);
  spec.body = body.name;
  spec.face = one_of(required(at, "face", "face name"), face_names(body.geometry), "face");
  spec.pressure = number(required(at, "pressure", "pressure, Pa, positive pushes into the body"));
  if (const Located function = child(at, "function"); function.node.IsDefined())
    spec.function = time_function(function);
  return spec;
}

// A probe may name an FE body (nearest node) or an SPH body (nearest particle).
std::vector<ProbeSpec> CaseReader::probes(const Located& at, const Case& c) const {
  std::vector<ProbeSpec> out;
  for (const Located& item : items(at)) {
    check_map(item, {"name", "body", "point"});
    ProbeSpec spec;
    const Located name = required(item, "name", "probe name");
    spec.name = text(name);
    if (!is_name(spec.name, ""))
      fail(name, "invalid probe name '" + spec.name + "' (use letters, digits and _)");
    if (std::ranges::find(out, spec.name, &ProbeSpec::name) != out.end())
      fail(name, "duplicate probe name '" + spec.name + "'");
    spec.body = body_ref(item, c.bodies).name;
    spec.point = vec3(required(item, "point", "position [x, y, z], m"));
    out.push_back(spec);
  }
  return out;
}

// The two distinct bodies named by `item`'s required "bodies" key. `earlier` holds the pairs
// before it in the same list, which it must not repeat (in either order); it is appended to.
std::array<const BodySpec*, 2> CaseReader::body_pair(const Located& item, const Case& c,
                                                     std::vector<BodyPair>& earlier) const {
  const Located list = required(item, "bodies", "the two bodies [a, b]");
  if (!list.node.IsSequence() || list.node.size() != 2)
    fail(list, "must be a list of 2 body names [a, b], got " + describe(list.node));
  Names names;
  for (const BodySpec& body : c.bodies)
    names.push_back(body.name);
  const std::vector<Located> given = items(list);
  const std::array<std::string, 2> pair{one_of(given[0], names, "body"),
                                        one_of(given[1], names, "body")};
  if (pair[0] == pair[1])
    fail(list, "must name two different bodies, got '" + pair[0] + "' twice");
  for (const auto& [seen, other] : earlier)
    if ((seen[0] == pair[0] && seen[1] == pair[1]) || (seen[0] == pair[1] && seen[1] == pair[0]))
      fail(list, "the pair '" + pair[0] + "', '" + pair[1] + "' is already given at " +
                     where(other) + " (" + other.path + ")");
  earlier.push_back({pair, item});
  return {&c.bodies[static_cast<std::size_t>(c.body_index(pair[0]))],
          &c.bodies[static_cast<std::size_t>(c.body_index(pair[1]))]};
}

// attach: [{bodies: [fem, sph]}, ...], the two in either order; an SPH body joins at most one
// FE body (its particles' sums would otherwise mix two FE bodies' background particles).
std::vector<AttachSpec> CaseReader::attachments(const Located& at, const Case& c) const {
  std::vector<AttachSpec> out;
  std::vector<BodyPair> done;
  for (const Located& item : items(at)) {
    check_map(item, {"bodies"});
    const auto [a, b] = body_pair(item, c, done);
    if (a->method == b->method)
      fail(child(item, "bodies"), "must name one fem body and one sph body, got '" + a->name +
                                      "' and '" + b->name + "', both " +
                                      (a->method == Method::Fem ? "fem" : "sph"));
    AttachSpec spec{a->method == Method::Fem ? a->name : b->name,
                    a->method == Method::Sph ? a->name : b->name};
    const auto same_sph = std::ranges::find(out, spec.sph_body, &AttachSpec::sph_body);
    if (same_sph != out.end())
      fail(child(item, "bodies"),
           "sph body '" + spec.sph_body + "' is already attached to '" + same_sph->fem_body +
               "' at " + where(done[static_cast<std::size_t>(same_sph - out.begin())].item) +
               " (an sph body attaches to at most one fem body)");
    out.push_back(spec);
  }
  return out;
}

// A contact law from a map with `model` (surface, the default, or kernel), `penalty`, `exponent`
// (kernel only) and `friction` (surface only), between bodies of materials a and b. A surface
// contact's penalty defaults to the smaller P-wave modulus of the two.
ContactSpec CaseReader::contact_law(const Located& at, const MaterialSpec& a,
                                    const MaterialSpec& b) const {
  ContactSpec spec;
  if (const Located model = child(at, "model"); model.node.IsDefined())
    spec.model = choice<ContactModel>(
        model, "contact model",
        {{"surface", ContactModel::Surface}, {"kernel", ContactModel::Kernel}});
  const auto only_for = [&](const char* key, const char* model, const char* why) {
    if (const Located given = child(at, key); given.node.IsDefined())
      fail(given, std::string("only for model: ") + model + " (" + why + ")");
  };
  if (spec.model == ContactModel::Kernel) {
    only_for("friction", "surface", "the kernel contact has no tangent plane");
    spec.penalty = number(required(at, "penalty", "penalty pressure K, Pa"), "> 0 Pa", positive);
    spec.exponent = number_or(at, "exponent", spec.exponent, "> 0", positive);
  } else {
    only_for("exponent", "kernel", "the surface contact's force is linear in the penetration");
    const double modulus = std::min(ElasticConstants::from(a).p_wave_modulus(),
                                    ElasticConstants::from(b).p_wave_modulus());
    spec.penalty = number_or(at, "penalty", modulus, "> 0 Pa", positive);
    spec.friction = number_or(at, "friction", 0.0, ">= 0", non_negative);
  }
  return spec;
}

// contact: [{bodies: [a, b], model, penalty, exponent, friction}, ...]. Attached bodies act as
// one body, whose entities never meet through contact (METHOD.md §4.3), so they cannot be a pair.
std::vector<ContactSpec> CaseReader::contacts(const Located& at, const Case& c) const {
  std::vector<ContactSpec> out;
  std::vector<BodyPair> done;
  for (const Located& item : items(at)) {
    check_map(item, {"bodies", "model", "penalty", "exponent", "friction"});
    const auto [a, b] = body_pair(item, c, done);
    for (const AttachSpec& attach : c.attachments)
      if ((attach.fem_body == a->name && attach.sph_body == b->name) ||
          (attach.fem_body == b->name && attach.sph_body == a->name))
        fail(child(item, "bodies"), "'" + a->name + "' and '" + b->name +
                                        "' are attached (one body): they cannot also be in "
                                        "contact");
    ContactSpec spec = contact_law(item, c.material(a->material), c.material(b->material));
    spec.bodies = {a->name, b->name};
    out.push_back(spec);
  }
  return out;
}

FemSpec CaseReader::fem(const Located& at) const {
  check_map(at, {"hourglass", "bulk_viscosity"});
  FemSpec spec;
  if (const Located hourglass = child(at, "hourglass"); hourglass.node.IsDefined()) {
    check_map(hourglass, {"form", "coefficient"});
    if (const Located form = child(hourglass, "form"); form.node.IsDefined())
      spec.hourglass_form = choice<HourglassForm>(
          form, "hourglass form",
          {{"viscous", HourglassForm::Viscous}, {"stiffness", HourglassForm::Stiffness}});
    spec.hourglass_coefficient =
        number_or(hourglass, "coefficient", spec.hourglass_coefficient, ">= 0", non_negative);
  }
  if (const Located bulk = child(at, "bulk_viscosity"); bulk.node.IsDefined()) {
    check_map(bulk, {"linear", "quadratic"});
    spec.bulk_viscosity_linear =
        number_or(bulk, "linear", spec.bulk_viscosity_linear, ">= 0", non_negative);
    spec.bulk_viscosity_quadratic =
        number_or(bulk, "quadratic", spec.bulk_viscosity_quadratic, ">= 0", non_negative);
  }
  return spec;
}

// Each of the three optional terms is absent (on, defaults), false (off), true (on, defaults)
// or a map of its parameters (on; missing ones default).
SphSpec CaseReader::sph(const Located& at) const {
  check_map(at, {"artificial_viscosity", "artificial_stress", "xsph", "variable_smoothing_length",
                 "gradient_correction", "cfl", "skin"});
  SphSpec spec;
  if (const Located av = child(at, "artificial_viscosity"); av.node.IsDefined()) {
    spec.artificial_viscosity = term(av, {"alpha", "beta", "balsara"});
    if (av.node.IsMap()) {
      spec.alpha = number_or(av, "alpha", spec.alpha, ">= 0", non_negative);
      spec.beta = number_or(av, "beta", spec.beta, ">= 0", non_negative);
      if (const Located balsara = child(av, "balsara"); balsara.node.IsDefined())
        spec.balsara = flag(balsara);
    }
  }
  if (const Located as = child(at, "artificial_stress"); as.node.IsDefined()) {
    spec.artificial_stress = term(as, {"epsilon", "n"});
    if (as.node.IsMap()) {
      spec.epsilon = number_or(as, "epsilon", spec.epsilon, ">= 0", non_negative);
      spec.stress_exponent = number_or(as, "n", spec.stress_exponent, "a positive integer",
                                       [](double v) { return v >= 1 && v == std::floor(v); });
    }
  }
  if (const Located xsph = child(at, "xsph"); xsph.node.IsDefined()) {
    spec.xsph = term(xsph, {"epsilon"});
    if (xsph.node.IsMap())
      spec.xsph_epsilon = number_or(xsph, "epsilon", spec.xsph_epsilon, ">= 0", non_negative);
  }
  if (const Located variable = child(at, "variable_smoothing_length"); variable.node.IsDefined())
    spec.variable_h = flag(variable);
  if (const Located correction = child(at, "gradient_correction"); correction.node.IsDefined())
    spec.gradient_correction = flag(correction);
  spec.cfl = number_or(at, "cfl", spec.cfl, "in (0, 1]", [](double v) { return v > 0 && v <= 1; });
  spec.skin = number_or(at, "skin", spec.skin, ">= 0 (a fraction of the largest 2h)", non_negative);
  return spec;
}

OutputSpec CaseReader::output(const Located& at) const {
  check_map(at, {"frames", "section", "checkpoint"});
  OutputSpec spec;
  if (const Located frames = child(at, "frames"); frames.node.IsDefined())
    spec.frames = flag(frames);
  if (const Located checkpoint = child(at, "checkpoint"); checkpoint.node.IsDefined()) {
    check_map(checkpoint, {"steps", "wall_s"});
    const double steps =
        number_or(checkpoint, "steps", 0.0, "a whole number of steps >= 0 (0: not by steps)",
                  [](double v) { return v >= 0 && v < 1e15 && v == std::floor(v); });
    spec.checkpoint.steps = static_cast<long long>(steps);
    spec.checkpoint.wall_s =
        number_or(checkpoint, "wall_s", spec.checkpoint.wall_s, ">= 0 s (0: not by time)",
                  [](double v) { return v >= 0 && std::isfinite(v); });
  }
  if (const Located section = child(at, "section"); section.node.IsDefined()) {
    check_map(section, {"point", "normal", "u_range"});
    SectionPlane plane;
    plane.point = vec3(required(section, "point", "a point on the plane [x, y, z], m"));
    const Located normal = required(section, "normal", "the plane's normal [x, y, z]");
    plane.normal = vec3(normal);
    if (!(plane.normal.norm() > 0))
      fail(normal, "must be a non-zero vector");
    plane.normal.normalize();
    if (const Located range = child(section, "u_range"); range.node.IsDefined()) {
      if (!range.node.IsSequence() || range.node.size() != 2)
        fail(range, "must be a list of 2 numbers [u0, u1] (m along the section's u axis), got " +
                        describe(range.node));
      const std::vector<Located> u = items(range);
      plane.u_range = std::array<double, 2>{number(u[0]), number(u[1])};
      if (!((*plane.u_range)[0] < (*plane.u_range)[1]))
        fail(range, "must be [u0, u1] with u0 < u1, got [" + describe(u[0].node) + ", " +
                        describe(u[1].node) + "]");
    }
    spec.section = plane;
  }
  return spec;
}

// A material library holds only `materials`; any other file is read as a whole case.
std::vector<MaterialSpec> CaseReader::read_materials(const YAML::Node& node) const {
  if (!node.IsMap() || node.size() != 1 || !node["materials"])
    return read(node).materials;
  const Located root{node, ""};
  std::vector<MaterialSpec> out;
  for (const Entry& entry :
       named_entries(required(root, "materials", "materials by name"), "material"))
    out.push_back(material(entry));
  return out;
}

// name, time and materials: what every case has.
Case CaseReader::common(const Located& root) const {
  Case c;
  const Located name = required(root, "name", "case name");
  c.name = text(name);
  if (!is_name(c.name, "-."))
    fail(name, "invalid case name '" + c.name + "' (use letters, digits, _, - and .)");
  c.time = time(required(root, "time", "time control: end, output_interval"));
  for (const Entry& entry :
       named_entries(required(root, "materials", "materials by name"), "material"))
    c.materials.push_back(material(entry));
  return c;
}

// fem, sph and output: the options every case may have.
void CaseReader::options(const Located& root, Case& c) const {
  if (const Located section = child(root, "fem"); section.node.IsDefined())
    c.fem = fem(section);
  if (const Located section = child(root, "sph"); section.node.IsDefined())
    c.sph = sph(section);
  if (const Located section = child(root, "output"); section.node.IsDefined())
    c.output = output(section);
}

// scene: <name> (solver/scenes/scene.hpp): the scene reads its own blocks and expands them into
// bodies, couplings and conditions; probes come after, since they name the bodies it made.
Case CaseReader::scene(const Located& root, const Located& name) const {
  Names names;
  for (const SceneType& type : scene_types())
    names.push_back(type.name);
  const std::string chosen = one_of(name, names, "scene");
  const SceneType& type = *std::ranges::find(scene_types(), chosen, &SceneType::name);
  Names allowed{"name", "scene", "time", "materials", "probes", "fem", "sph", "output"};
  allowed.insert(allowed.end(), type.keys.begin(), type.keys.end());
  check_map(root, allowed);
  Case c = common(root);
  options(root, c);
  type.read(CaseNode(*this, root.node, root.path), c);
  if (const Located list = child(root, "probes"); list.node.IsDefined())
    c.probes = probes(list, c);
  return c;
}

Case CaseReader::read(const YAML::Node& node) const {
  const Located root{node, ""};
  if (!node.IsMap()) // before looking up `scene`, which yaml-cpp refuses on a single value
    fail(root, "must be a map, got " + describe(node));
  if (const Located name = child(root, "scene"); name.node.IsDefined())
    return scene(root, name);
  check_map(root, {"name", "time", "materials", "bodies", "boundary_conditions", "loads", "probes",
                   "attach", "contact", "fem", "sph", "output"});
  Case c = common(root);
  for (const Entry& entry : named_entries(required(root, "bodies", "bodies by name"), "body"))
    c.bodies.push_back(body(entry, c.materials));
  if (const Located list = child(root, "boundary_conditions"); list.node.IsDefined())
    for (const Located& item : items(list))
      c.boundary_conditions.push_back(boundary_condition(item, c));
  if (const Located list = child(root, "loads"); list.node.IsDefined())
    for (const Located& item : items(list))
      c.loads.push_back(load(item, c));
  if (const Located list = child(root, "probes"); list.node.IsDefined())
    c.probes = probes(list, c);
  if (const Located list = child(root, "attach"); list.node.IsDefined())
    c.attachments = attachments(list, c);
  if (const Located list = child(root, "contact"); list.node.IsDefined())
    c.contacts = contacts(list, c);
  options(root, c);
  return c;
}

// ---- CaseNode: the checks above, for a scene's blocks -------------------------------------

void CaseNode::check_keys(const Names& allowed) const {
  reader_->check_map({node_, path_}, allowed);
}

CaseNode CaseNode::child(const std::string& key) const {
  const Located at = reader_->child({node_, path_}, key);
  return {*reader_, at.node, at.path};
}

CaseNode CaseNode::required(const std::string& key, std::string_view meaning) const {
  const Located at = reader_->required({node_, path_}, key, meaning);
  return {*reader_, at.node, at.path};
}

double CaseNode::number(std::string_view rule, Rule ok) const {
  return reader_->number({node_, path_}, rule, ok);
}

double CaseNode::number_or(const std::string& key, double fallback, std::string_view rule,
                           Rule ok) const {
  return reader_->number_or({node_, path_}, key, fallback, rule, ok);
}

std::string CaseNode::one_of(const Names& names, std::string_view what) const {
  return reader_->one_of({node_, path_}, names, what);
}

// An absent block is an empty map: every key of the law at its default. (YAML::Node's
// assignment writes into the node it refers to, so an absent node is replaced, not assigned.)
ContactSpec CaseNode::contact_law(const MaterialSpec& a, const MaterialSpec& b) const {
  const Located at{node_.IsDefined() ? node_ : YAML::Node(YAML::NodeType::Map), path_};
  reader_->check_map(at, {"model", "penalty", "exponent", "friction"});
  return reader_->contact_law(at, a, b);
}

void CaseNode::fail(const std::string& label, const std::string& what) const {
  reader_->fail({node_, path_}, label, what);
}

namespace {

// Parses `yaml_text`, applies the overrides and hands the tree to `read(reader, root)`,
// turning YAML and other failures into located errors.
template <class Read>
auto parse(const std::string& yaml_text, const std::filesystem::path& file,
           const std::vector<std::string>& overrides, Read read) {
  const std::string name = file.string();
  try {
    YAML::Node root = YAML::Load(yaml_text);
    std::vector<std::string> override_paths;
    for (const std::string& text : overrides)
      override_paths.push_back(apply_override(root, text));
    std::error_code no_folder;
    const std::filesystem::path folder = std::filesystem::absolute(file, no_folder).parent_path();
    resolve_material_libraries(root, folder, name);
    return read(CaseReader(name, folder, std::move(override_paths)), root);
  } catch (const Error&) {
    throw;
  } catch (const YAML::ParserException& e) {
    throw Error(name + ":" + line_of(e.mark) + ": YAML syntax error: " + e.msg);
  } catch (const std::exception& e) {
    throw Error(name + ": cannot read the case: " + e.what());
  }
}

std::string file_text(const std::filesystem::path& file, std::string_view what) {
  std::error_code ignored;
  if (std::filesystem::is_directory(file, ignored))
    throw Error(file.string() + ": cannot open the " + std::string(what) + " (it is a directory)");
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw Error(file.string() + ": cannot open the " + std::string(what) + " (" +
                std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

} // namespace

Case read_case_text(const std::string& yaml_text, const std::filesystem::path& file,
                    const std::vector<std::string>& overrides) {
  Case result =
      parse(yaml_text, file, overrides, [](const CaseReader& reader, const YAML::Node& root) {
        Case c = reader.read(root);
        flatten(root, "", c.keys);
        return c;
      });
  result.file = file;
  return result;
}

Case read_case(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  return read_case_text(file_text(file, "case file"), file, overrides);
}

std::vector<MaterialSpec> read_materials_text(const std::string& yaml_text,
                                              const std::filesystem::path& file,
                                              const std::vector<std::string>& overrides) {
  return parse(yaml_text, file, overrides, [](const CaseReader& reader, const YAML::Node& root) {
    return reader.read_materials(root);
  });
}

std::vector<MaterialSpec> read_materials(const std::filesystem::path& file,
                                         const std::vector<std::string>& overrides) {
  return read_materials_text(file_text(file, "materials file"), file, overrides);
}

} // namespace sphfem
