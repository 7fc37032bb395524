#include "solver/time/restart_check.hpp"

#include "solver/core/error.hpp"

#include <array>
#include <set>
#include <string_view>

namespace sphfem {

bool output_only_key(const std::string& path) {
  constexpr std::array<std::string_view, 5> keys{"name", "time.end", "time.output_interval",
                                                 "time.history_interval", "time.energy_limit"};
  for (std::string_view k : keys)
    if (path == k)
      return true;
  return path == "output" || path.starts_with("output.");
}

std::vector<std::string> differing_physics_keys(const std::map<std::string, std::string>& before,
                                                const std::map<std::string, std::string>& now) {
  std::set<std::string> paths;
  for (const auto& [k, v] : before)
    paths.insert(k);
  for (const auto& [k, v] : now)
    paths.insert(k);
  std::vector<std::string> out;
  for (const auto& k : paths) {
    if (output_only_key(k))
      continue;
    const auto b = before.find(k), n = now.find(k);
    const std::string vb = b == before.end() ? "(none)" : b->second;
    const std::string vn = n == now.end() ? "(none)" : n->second;
    if (vb != vn || (b == before.end()) != (n == now.end()))
      out.push_back(k + ": checkpoint " + vb + ", case " + vn);
  }
  return out;
}

void check_restart_case(const std::filesystem::path& file, const CheckpointMeta& meta,
                        const Case& c) {
  const std::vector<std::string> differ = differing_physics_keys(meta.case_keys, c.keys);
  if (differ.empty())
    return;
  std::string keys;
  for (std::size_t k = 0; k < differ.size() && k < 8; ++k)
    keys += (k ? "; " : "") + differ[k];
  if (differ.size() > 8)
    keys += "; and " + std::to_string(differ.size() - 8) + " more";
  throw Error(
      detail::concat("checkpoint ", file, ": the case's physics differs from the ",
                     "checkpoint's (only time.end, time.output_interval, ",
                     "time.history_interval, time.energy_limit and output.* may change): ", keys));
}

} // namespace sphfem
