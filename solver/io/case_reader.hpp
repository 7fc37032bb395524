// Reading a case file: parse the YAML, apply command-line overrides, validate everything
// against the schema and build a Case. Every problem is reported as one sphfem::Error line
// "<file>:<line>: <key.path>: <what was expected, and what was found>".
#pragma once

#include "solver/io/case.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace sphfem {

// Reads `file`, applies the overrides ("key.path=value", value parsed as YAML; the path walks
// maps by key and lists by index) in order, and validates. A problem with a value that came
// from an override is located as "--set <key.path>" instead of "<file>:<line>". Geometry file
// paths (bodies.<name>.geometry.file) are relative to the case file's folder.
Case read_case(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});

// Same, from text; `file` is used in messages and as Case::file, and relative geometry file
// paths (bodies.<name>.geometry.file) start from its folder. Case::bodies hold them absolute.
Case read_case_text(const std::string& yaml_text, const std::filesystem::path& file,
                    const std::vector<std::string>& overrides = {});

// The materials of a material library (a file holding only `materials:`, as in
// cases/materials/) or of a whole case file, validated as read_case() validates them.
std::vector<MaterialSpec> read_materials(const std::filesystem::path& file,
                                         const std::vector<std::string>& overrides = {});
std::vector<MaterialSpec> read_materials_text(const std::string& yaml_text,
                                              const std::filesystem::path& file,
                                              const std::vector<std::string>& overrides = {});

} // namespace sphfem
