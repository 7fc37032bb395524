// A block of the case file as a scene (solver/scenes/) reads it: a YAML node with its key path
// and the case reader's checks, so that a scene's messages read as every other section's do:
// "<file>:<line>: <key.path>: <what was expected, and what was found>", or "--set <key.path>: …"
// for a value given by an override. Defined beside the reader, in case_reader.cpp; verified
// through the scenes' tests (tests/scenes/).
#pragma once

#include "solver/io/case.hpp"

#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>
#include <vector>

namespace sphfem {

class CaseReader; // solver/io/case_reader.cpp

class CaseNode {
public:
  using Names = std::vector<std::string_view>;
  using Rule = bool (*)(double);

  CaseNode(const CaseReader& reader, YAML::Node node, std::string path)
      : reader_(&reader), node_(std::move(node)), path_(std::move(path)) {}

  const std::string& path() const { return path_; }
  bool defined() const { return node_.IsDefined(); }

  // Structure: only the `allowed` keys (an error names the unknown one and lists these);
  // a child, undefined when absent; a child that must be there (`meaning` says what it holds).
  void check_keys(const Names& allowed) const;
  CaseNode child(const std::string& key) const;
  CaseNode required(const std::string& key, std::string_view meaning) const;

  // Values: a number that `ok` accepts (`rule` says how, "> 0 m"), the number at `key` or
  // `fallback` when absent, one of `names` (`what` names the choice in the message).
  double number(std::string_view rule, Rule ok) const;
  double number_or(const std::string& key, double fallback, std::string_view rule, Rule ok) const;
  std::string one_of(const Names& names, std::string_view what) const;

  // A contact law (model, penalty, exponent, friction) between the two materials, as a
  // `contact` item reads it (docs/contact.md); this node holds its keys, or is undefined.
  ContactSpec contact_law(const MaterialSpec& a, const MaterialSpec& b) const;

  // Reports `what` at this node under the key path `label` (the scene's own checks, made after
  // its parameters are read: "plate.yaml:1: scene plate_impact: core.spacing: …").
  [[noreturn]] void fail(const std::string& label, const std::string& what) const;

private:
  const CaseReader* reader_;
  YAML::Node node_;
  std::string path_;
};

} // namespace sphfem
