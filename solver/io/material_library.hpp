// Materials taken from a library file (cases/materials/*.yaml): a case's material entry
//   plate: {library: ../materials/weldox460e.yaml, entry: weldox460e, <keys to change>}
// becomes the library's entry (`entry` defaults to the case's own name for the material) with
// the given keys merged over it, maps key by key (so `johnson_cook: {C: 0.012}` changes C
// only). The library file is validated on its own first, so its errors name its own lines;
// the path is relative to the case file's folder. A library that refers back to a file being
// read (itself, or through others) is an error naming the cycle.
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>

namespace sphfem {

// Replaces every library reference under root["materials"] in place. `file` names the case
// in messages; `folder` is where relative library paths start.
void resolve_material_libraries(YAML::Node& root, const std::filesystem::path& folder,
                                const std::string& file);

} // namespace sphfem
