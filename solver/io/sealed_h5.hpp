// Sealed HDF5 files (model.h5, checkpoint.h5): the file begins with a 512-byte user block, which
// HDF5 skips, holding a text seal — the number of bytes after the block and their 64-bit FNV-1a
// hash. A reader checks the seal before HDF5 reads the file: HDF5 1.10 decodes corrupt object
// headers without bounds checks (its attribute decoder reads beyond its buffers, found by
// fuzzing: fuzz/regressions/model_h5/hdf5_*), so a damaged file must never reach it. A file whose
// seal matches is one sphfem wrote whole; the seal does not guard against deliberate forgery.
#pragma once

#include <H5Cpp.h>

#include <filesystem>

namespace sphfem {

// File creation properties of a sealed file: the user block that will hold the seal.
H5::FileCreatPropList sealed_file_properties();

// Writes the seal into `file`, a closed HDF5 file created with sealed_file_properties().
void seal_h5_file(const std::filesystem::path& file);

// An Error unless `file` is a regular file whose seal matches its content; the message says
// what it is instead (no such file, not an HDF5 file, no seal, truncated, changed), and the
// caller prefixes what the file was to be.
void check_h5_seal(const std::filesystem::path& file);

} // namespace sphfem
