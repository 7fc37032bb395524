// OUT/checkpoint.h5: the complete state of a run, to continue it with
// `sphfem solve CASE -o OUT --restart OUT/checkpoint.h5` (DESIGN.md, Files). Layout: root
// attributes `format` ("sphfem-checkpoint") and `version` (2: sealed, sealed_h5.hpp); /meta — time,
// step, thread count, the model's fingerprint and the case's keys as parsed; then every field the
// run's persist() functions name (StateArchive), each a dataset of its bytes with the element size
// as an attribute. Written to a temporary name and renamed, so the previous checkpoint stays whole
// until the new one is. Reading refuses, with a message naming the file, anything that is not
// a complete checkpoint of this version and layout. Verified by tests/io/checkpoint_test.cpp
// and tests/e2e/restart_test.cpp.
#pragma once

#include "solver/io/state_archive.hpp"
#include "solver/state/model.hpp"

#include <filesystem>
#include <functional>
#include <map>
#include <string>

namespace sphfem {

struct CheckpointMeta {
  double time = 0; // s
  long long steps = 0;
  int threads = 1;
  std::string model; // model_fingerprint() of the model the run was built from
  std::map<std::string, std::string> case_keys; // Case::keys
};

// Writes `file` (atomically): the meta, then the fields `persist` stores.
void write_checkpoint(const std::filesystem::path& file, const CheckpointMeta& meta,
                      const std::function<void(StateArchive&)>& persist);

// The meta of a checkpoint; an Error naming `file` if it is not a readable checkpoint.
CheckpointMeta read_checkpoint_meta(const std::filesystem::path& file);

// Reads the fields `persist` names back from `file`; an Error naming the file and the field for
// one that is absent or of another layout.
void read_checkpoint(const std::filesystem::path& file,
                     const std::function<void(StateArchive&)>& persist);

// A fingerprint of a model's content (counts and a 64-bit FNV-1a hash of its nodes, elements,
// particles and coupling data, in hexadecimal): equal for the same mesh, whatever file holds it.
std::string model_fingerprint(const Model& model);

} // namespace sphfem
