#include "solver/io/material_library.hpp"

#include "solver/core/error.hpp"
#include "solver/io/case_reader.hpp"

#include <algorithm>

namespace sphfem {

namespace {

// `over` merged into a copy of `base`: maps key by key, anything else replaced.
YAML::Node merged(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap())
    return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  for (const auto& pair : over) {
    const std::string key = pair.first.Scalar();
    const YAML::Node existing = out[key];
    out[key] = existing.IsDefined() ? merged(existing, pair.second) : YAML::Clone(pair.second);
  }
  return out;
}

} // namespace

void resolve_material_libraries(YAML::Node& root, const std::filesystem::path& folder,
                                const std::string& file) {
  if (!root.IsMap() || !root["materials"] || !root["materials"].IsMap())
    return;
  YAML::Node materials = root["materials"];
  for (auto pair : materials) {
    YAML::Node entry = pair.second;
    if (!entry.IsMap() || !entry["library"])
      continue;
    const std::string name = pair.first.Scalar();
    const std::string path = "materials." + name;
    const auto fail = [&](const YAML::Node& at, const std::string& key, const std::string& what) {
      throw Error(file + ":" + std::to_string(std::max(at.Mark().line, 0) + 1) + ": " + path + "." +
                  key + ": " + what);
    };
    const YAML::Node library = entry["library"];
    if (!library.IsScalar())
      fail(library, "library", "must be a file name (a material library, cases/materials/)");
    std::filesystem::path library_file = library.Scalar();
    if (library_file.is_relative())
      library_file = folder / library_file;
    if (std::error_code error; !std::filesystem::is_regular_file(library_file, error))
      fail(library, "library", library_file.string() + ": no such file");
    std::string wanted = name;
    if (const YAML::Node given = entry["entry"]; given) {
      if (!given.IsScalar())
        fail(given, "entry", "must be the name of a material in the library");
      wanted = given.Scalar();
    }
    std::string available;
    for (const MaterialSpec& m : read_materials(library_file)) // validates the library
      available += (available.empty() ? "" : ", ") + m.name;
    const YAML::Node source = YAML::LoadFile(library_file.string())["materials"][wanted];
    if (!source.IsDefined())
      fail(entry["entry"] ? entry["entry"] : library, entry["entry"] ? "entry" : "library",
           library_file.string() + " has no material '" + wanted + "' (it has: " + available + ")");
    YAML::Node changes = YAML::Clone(entry);
    changes.remove("library");
    changes.remove("entry");
    materials[name] = merged(source, changes);
  }
}

} // namespace sphfem
