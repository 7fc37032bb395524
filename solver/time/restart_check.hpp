// What a restart may change: a checkpoint continues a run only under the physics it was made
// with. Output-only keys — the end time, the output and history intervals, the case's name and
// everything under `output` (frames, section, checkpoint cadence) — may differ; any other key
// that differs, appears or disappears refuses the restart. Verified by
// tests/e2e/restart_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/io/checkpoint.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace sphfem {

bool output_only_key(const std::string& path);

// "key: checkpoint V, case W" for each physics key whose value differs (absent: "(none)").
std::vector<std::string> differing_physics_keys(const std::map<std::string, std::string>& before,
                                                const std::map<std::string, std::string>& now);

// An Error naming the differing keys (at most eight) unless the checkpoint `file` with `meta`
// may continue under case `c`. Checked before anything is meshed or written.
void check_restart_case(const std::filesystem::path& file, const CheckpointMeta& meta,
                        const Case& c);

} // namespace sphfem
