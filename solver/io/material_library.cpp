// Material entries taken from library files: resolved, merged and checked (see the header).
#include "solver/io/material_library.hpp"

#include "solver/core/error.hpp"
#include "solver/io/case_reader.hpp"

#include <algorithm>
#include <filesystem>
#include <utility>
#include <vector>

namespace sphfem {

namespace {

// `over` merged into a copy of `base`: maps key by key, anything else replaced. The values
// taken from `over` are its own nodes, not copies, so that they keep their lines for messages.
YAML::Node merged(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap())
    return over;
  YAML::Node out = YAML::Clone(base);
  for (const auto& pair : over) {
    const std::string key = pair.first.Scalar();
    const YAML::Node existing = out[key];
    out[key] = existing.IsDefined() ? merged(existing, pair.second) : pair.second;
  }
  return out;
}

// The library files being read, outermost first: a library that refers back to one of them
// (itself, or through others) would be read forever.
thread_local std::vector<std::filesystem::path> libraries_open;

struct OpenLibrary {
  explicit OpenLibrary(std::filesystem::path file) { libraries_open.push_back(std::move(file)); }
  ~OpenLibrary() { libraries_open.pop_back(); }
  OpenLibrary(const OpenLibrary&) = delete;
  OpenLibrary& operator=(const OpenLibrary&) = delete;
};

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
    std::error_code no_path;
    const std::filesystem::path canonical =
        std::filesystem::weakly_canonical(library_file, no_path);
    if (std::ranges::find(libraries_open, canonical) != libraries_open.end()) {
      std::string cycle;
      for (const auto& open : libraries_open)
        cycle += open.string() + " -> ";
      fail(library, "library",
           library_file.string() + ": the libraries refer to each other in a cycle (" + cycle +
               canonical.string() + ")");
    }
    std::string available;
    {
      const OpenLibrary open(canonical);
      for (const MaterialSpec& m : read_materials(library_file)) // validates the library
        available += (available.empty() ? "" : ", ") + m.name;
    }
    const YAML::Node source = YAML::LoadFile(library_file.string())["materials"][wanted];
    if (!source.IsDefined())
      fail(entry["entry"] ? entry["entry"] : library, entry["entry"] ? "entry" : "library",
           library_file.string() + " has no material '" + wanted + "' (it has: " + available + ")");
    YAML::Node changes(YAML::NodeType::Map);
    for (const auto& pair : entry)
      if (const std::string key = pair.first.Scalar(); key != "library" && key != "entry")
        changes[key] = pair.second;
    materials[name] = merged(source, changes);
  }
}

} // namespace sphfem
