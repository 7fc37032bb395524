// Crash-safe file replacement: write to "<file>.tmp", then rename over <file>, so a reader or
// a crash never sees a half-written file (DESIGN.md, Files); a write that throws removes its
// temporary and leaves <file> as it was.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace sphfem {

void write_atomically(const std::filesystem::path& file,
                      const std::function<void(const std::filesystem::path& temporary)>& write);

// Convenience for text files.
void write_text_atomically(const std::filesystem::path& file, const std::string& text);

} // namespace sphfem
