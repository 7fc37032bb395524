#include "solver/io/checkpoint.hpp"

#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/io/fnv1a.hpp"
#include "solver/io/hdf5_errors.hpp"
#include "solver/io/sealed_h5.hpp"

#include <H5Cpp.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>

namespace sphfem {

namespace {

namespace fs = std::filesystem;

constexpr const char* format_name = "sphfem-checkpoint";
// Version 2: the file is sealed (sealed_h5.hpp).
constexpr int format_version = 2;

// Fields as byte datasets [count × element bytes] with the element size as an attribute.
class H5Archive final : public StateArchive {
public:
  H5Archive(H5::H5File& file, bool reading) : file_(file), reading_(reading) {}
  bool reading() const override { return reading_; }

protected:
  std::size_t stored_count(const std::string& name, std::size_t element) override {
    return dimensions(name, element)[0];
  }
  void bytes(const std::string& name, void* data, std::size_t count, std::size_t element) override {
    if (reading_) {
      const auto dims = dimensions(name, element);
      SPHFEM_CHECK(dims[0] == count, "field ", name, ": ", dims[0], " values stored, ", count,
                   " expected");
      if (count > 0)
        file_.openDataSet(name).read(data, H5::PredType::NATIVE_UCHAR);
      return;
    }
    const std::array<hsize_t, 2> dims{count, element};
    H5::LinkCreatPropList link;
    link.setCreateIntermediateGroup(true);
    // No modification times in the objects: the same state gives the same file, byte for byte.
    H5::DSetCreatPropList untimed;
    H5Pset_obj_track_times(untimed.getId(), false);
    const H5::DataSet dataset =
        file_.createDataSet(name, H5::PredType::NATIVE_UCHAR, H5::DataSpace(2, dims.data()),
                            untimed, H5::DSetAccPropList::DEFAULT, link);
    if (count > 0)
      dataset.write(data, H5::PredType::NATIVE_UCHAR);
    const int bytes = static_cast<int>(element);
    dataset.createAttribute("element_bytes", H5::PredType::STD_I32LE, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_INT, &bytes);
  }

private:
  // Whether every link of the path "a/b/c" exists (H5Lexists needs its parents to).
  bool exists(const std::string& name) const {
    for (std::size_t slash = name.find('/');; slash = name.find('/', slash + 1)) {
      if (!file_.nameExists(name.substr(0, slash)))
        return false;
      if (slash == std::string::npos)
        return true;
    }
  }
  std::array<hsize_t, 2> dimensions(const std::string& name, std::size_t element) const {
    SPHFEM_CHECK(exists(name), "field ", name, " is missing (written by another version?)");
    const H5::DataSet dataset = file_.openDataSet(name);
    const H5::DataSpace space = dataset.getSpace();
    std::array<hsize_t, 2> dims{0, 0};
    SPHFEM_CHECK(space.getSimpleExtentNdims() == 2, "field ", name, ": not a field");
    space.getSimpleExtentDims(dims.data());
    int stored = 0;
    SPHFEM_CHECK(dataset.attrExists("element_bytes"), "field ", name, ": no element size");
    dataset.openAttribute("element_bytes").read(H5::PredType::NATIVE_INT, &stored);
    SPHFEM_CHECK(stored == static_cast<int>(element) && dims[1] == element, "field ", name,
                 ": elements of ", stored, " bytes, this build's are ", element,
                 " (a checkpoint of another build or version)");
    // A corrupt header may claim any extent: refused unless the bytes are there.
    SPHFEM_CHECK(static_cast<double>(dims[0]) * element <= double(dataset.getStorageSize()),
                 "field ", name, " claims more data than the file holds: the file is corrupt");
    return dims;
  }

  H5::H5File& file_;
  bool reading_;
};

// The meta block, through the archive like every other field.
void persist_meta(StateArchive& a, CheckpointMeta& meta) {
  a.value("meta/time", meta.time);
  a.value("meta/steps", meta.steps);
  a.value("meta/threads", meta.threads);
  a.text("meta/model", meta.model);
  std::string keys = nlohmann::json(meta.case_keys).dump();
  a.text("meta/case_keys", keys);
  if (a.reading())
    meta.case_keys = nlohmann::json::parse(keys).get<std::map<std::string, std::string>>();
}

// Opens a checkpoint for reading after checking what it is; `read` gets the file.
template <class Read> auto read_file(const fs::path& file, Read read) {
  const Hdf5Errors errors;
  try {
    check_h5_seal(file);
    H5::H5File h5(file.string(), H5F_ACC_RDONLY);
    SPHFEM_CHECK(h5.attrExists("format") && h5.attrExists("version"),
                 "not a checkpoint (no format attribute)");
    const H5::Attribute attribute = h5.openAttribute("format");
    const std::size_t bytes = attribute.getStorageSize();
    SPHFEM_CHECK(attribute.getTypeClass() == H5T_STRING &&
                     !attribute.getStrType().isVariableStr() && bytes < 256,
                 "not a checkpoint (its format attribute is not a short string)");
    std::string format(bytes, '\0');
    attribute.read(attribute.getStrType(), format.data());
    SPHFEM_CHECK(format == format_name, "not a checkpoint (format \"", format, "\")");
    int version = 0;
    h5.openAttribute("version").read(H5::PredType::NATIVE_INT, &version);
    SPHFEM_CHECK(version == format_version, "checkpoint version ", version, ", this sphfem reads ",
                 format_version);
    H5Archive archive(h5, true);
    return read(archive);
  } catch (const H5::Exception& e) {
    throw Error(detail::concat("checkpoint ", file, ": HDF5 cannot read it: ", errors.describe(e)));
  } catch (const nlohmann::json::exception& e) {
    throw Error(detail::concat("checkpoint ", file, ": unreadable case keys: ", e.what()));
  } catch (const Error& e) {
    throw Error(detail::concat("checkpoint ", file, ": ", e.what()));
  }
}

} // namespace

void write_checkpoint(const fs::path& file, const CheckpointMeta& meta,
                      const std::function<void(StateArchive&)>& persist) {
  write_atomically(file, [&](const fs::path& temporary) {
    const Hdf5Errors errors;
    try {
      H5::H5File h5(temporary.string(), H5F_ACC_TRUNC, sealed_file_properties());
      const std::string format = format_name;
      const H5::StrType text(H5::PredType::C_S1, format.size());
      const H5::DataSpace scalar(H5S_SCALAR);
      h5.createAttribute("format", text, scalar).write(text, format.data());
      h5.createAttribute("version", H5::PredType::STD_I32LE, scalar)
          .write(H5::PredType::NATIVE_INT, &format_version);
      H5Archive archive(h5, false);
      CheckpointMeta copy = meta;
      persist_meta(archive, copy);
      persist(archive);
      h5.close();
      seal_h5_file(temporary);
    } catch (const H5::Exception& e) {
      throw Error(
          detail::concat("checkpoint ", temporary, ": HDF5 cannot write it: ", errors.describe(e)));
    }
  });
}

CheckpointMeta read_checkpoint_meta(const fs::path& file) {
  return read_file(file, [](StateArchive& a) {
    CheckpointMeta meta;
    persist_meta(a, meta);
    return meta;
  });
}

void read_checkpoint(const fs::path& file, const std::function<void(StateArchive&)>& persist) {
  read_file(file, [&](StateArchive& a) {
    persist(a);
    return 0;
  });
}

std::string model_fingerprint(const Model& model) {
  Fnv1a f;
  for (const auto& name : model.body_names)
    f.add(std::vector<char>(name.c_str(), name.c_str() + name.size() + 1));
  f.add(model.x_n), f.add(model.body_n), f.add(model.hex_e), f.add(model.body_e);
  f.add(model.x_p), f.add(model.m_p), f.add(model.rho_p), f.add(model.h_p), f.add(model.body_p);
  f.add(model.spacing_b), f.add(model.background_nodes), f.add(model.h_background);
  f.add(model.spacing_background), f.add(model.interface_p);
  char text[128];
  std::snprintf(
      text, sizeof text, "%lld nodes, %lld hexahedra, %lld particles, %016llx",
      static_cast<long long>(model.node_count()), static_cast<long long>(model.element_count()),
      static_cast<long long>(model.particle_count()), static_cast<unsigned long long>(f.hash));
  return text;
}

} // namespace sphfem
