// Writes and reads model.h5 (layout in model_h5.hpp) with HDF5's C++ API; every HDF5 failure
// or malformed content becomes a sphfem::Error naming the file. Verified by
// tests/io/model_h5_test.cpp.
#include "solver/io/model_h5.hpp"

#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/io/hdf5_errors.hpp"
#include "solver/io/sealed_h5.hpp"

#include <H5Cpp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <system_error>

#ifndef SPHFEM_VERSION
#define SPHFEM_VERSION "0.1.0"
#endif

namespace sphfem {
namespace {

namespace fs = std::filesystem;

constexpr const char* format_name = "sphfem-model";
// Version 2: strings are fixed-length (version 1's variable-length strings let a corrupt file
// make HDF5 allocate gigabytes before any check of ours could run; found by fuzzing).
// Version 3: the file is sealed (sealed_h5.hpp; HDF5 read beyond its buffers on corrupt
// attribute headers, found by fuzzing).
constexpr int format_version = 3;
constexpr std::size_t longest_string = 65536; // bytes, for a name, signature or unit
constexpr hsize_t chunk_rows = 16384; // datasets longer than this are chunked and compressed

// HDF5 types per C++ element type: in memory, in the file, and the class a reader accepts.
template <class T> struct H5Type;
template <> struct H5Type<double> {
  static const H5::PredType& memory() { return H5::PredType::NATIVE_DOUBLE; }
  static const H5::PredType& file() { return H5::PredType::IEEE_F64LE; }
  static constexpr H5T_class_t type_class = H5T_FLOAT;
};
template <> struct H5Type<Index> {
  static const H5::PredType& memory() { return H5::PredType::NATIVE_INT32; }
  static const H5::PredType& file() { return H5::PredType::STD_I32LE; }
  static constexpr H5T_class_t type_class = H5T_INTEGER;
};

// A fixed-length UTF-8 string type holding `bytes` (at least 1: HDF5 has no empty type).
H5::StrType string_type(std::size_t bytes) {
  H5::StrType type(H5::PredType::C_S1, std::max<std::size_t>(bytes, 1));
  type.setCset(H5T_CSET_UTF8);
  type.setStrpad(H5T_STR_NULLPAD);
  return type;
}

template <class Range>
void check_indices(const Range& indices, std::size_t count, const std::string& what) {
  for (const Index i : indices)
    SPHFEM_CHECK(i >= 0 && static_cast<std::size_t>(i) < count, what, " holds index ", i,
                 " outside [0, ", count, ")");
}

// ---- writing ------------------------------------------------------------------------------

void write_attribute(const H5::H5Object& object, const std::string& name,
                     const std::string& value) {
  const H5::StrType type = string_type(value.size());
  object.createAttribute(name, type, H5::DataSpace(H5S_SCALAR)).write(type, value.data());
}

void write_attribute(const H5::H5Object& object, const std::string& name, int value) {
  object.createAttribute(name, H5::PredType::STD_I32LE, H5::DataSpace(H5S_SCALAR))
      .write(H5::PredType::NATIVE_INT, &value);
}

// Writes `values` as a rows × cols dataset (1-D when cols == 0) at `path` below `parent`,
// creating intermediate groups.
template <class T>
H5::DataSet write_array(const H5::Group& parent, const std::string& path,
                        const std::vector<T>& values, hsize_t cols = 0) {
  const hsize_t rows = values.size() / std::max<hsize_t>(cols, 1);
  const std::array<hsize_t, 2> dims{rows, cols};
  const H5::DataSpace space(cols == 0 ? 1 : 2, dims.data());
  H5::DSetCreatPropList create;
  if (rows > chunk_rows) {
    const std::array<hsize_t, 2> chunk{chunk_rows, cols};
    create.setChunk(cols == 0 ? 1 : 2, chunk.data());
    create.setShuffle();
    create.setDeflate(4);
  }
  H5::LinkCreatPropList link;
  link.setCreateIntermediateGroup(true);
  const H5::DataSet dataset = parent.createDataSet(path, H5Type<T>::file(), space, create,
                                                   H5::DSetAccPropList::DEFAULT, link);
  if (!values.empty())
    dataset.write(values.data(), H5Type<T>::memory());
  return dataset;
}

template <std::size_t C> std::vector<Index> flatten(const std::vector<std::array<Index, C>>& rows) {
  std::vector<Index> flat;
  flat.reserve(C * rows.size());
  for (const auto& row : rows)
    flat.insert(flat.end(), row.begin(), row.end());
  return flat;
}

std::vector<double> flatten(const std::vector<Vec3>& points) {
  std::vector<double> flat;
  flat.reserve(3 * points.size());
  for (const Vec3& p : points)
    flat.insert(flat.end(), p.data(), p.data() + 3);
  return flat;
}

void write_strings(const H5::Group& parent, const std::string& name,
                   const std::vector<std::string>& strings) {
  std::size_t width = 1;
  for (const std::string& s : strings)
    width = std::max(width, s.size());
  std::vector<char> packed(strings.size() * width, '\0');
  for (std::size_t i = 0; i < strings.size(); ++i)
    std::copy(strings[i].begin(), strings[i].end(), packed.begin() + i * width);
  const hsize_t n = strings.size();
  const H5::StrType type = string_type(width);
  const H5::DataSet dataset = parent.createDataSet(name, type, H5::DataSpace(1, &n));
  if (n > 0)
    dataset.write(packed.data(), type);
}

// A set name becomes an HDF5 path, so it must be a '/'-separated list of non-empty parts.
void check_set_name(const std::string& name) {
  const bool ok = !name.empty() && name.front() != '/' && name.back() != '/' &&
                  name.find("//") == std::string::npos && name != ".";
  SPHFEM_CHECK(ok, "set name '", name, "' cannot be stored");
}

template <class Sets> void write_sets(const H5::Group& group, const Sets& sets, hsize_t cols) {
  for (const auto& [name, items] : sets) {
    check_set_name(name);
    if constexpr (std::is_same_v<typename Sets::mapped_type, std::vector<Index>>)
      write_array(group, name, items);
    else
      write_array(group, name, flatten(items), cols);
  }
}

void write_particles(const H5::H5File& file, const Model& m) {
  const std::size_t p = m.x_p.size();
  SPHFEM_CHECK(m.m_p.size() == p && m.rho_p.size() == p && m.h_p.size() == p &&
                   m.body_p.size() == p,
               "particle arrays do not match the ", p, " particle positions");
  const H5::Group particles = file.createGroup("particles");
  write_attribute(write_array(particles, "x", flatten(m.x_p), 3), "units", "m");
  write_attribute(write_array(particles, "mass", m.m_p), "units", "kg");
  write_attribute(write_array(particles, "density", m.rho_p), "units", "kg/m^3");
  write_attribute(write_array(particles, "h", m.h_p), "units", "m");
  write_array(particles, "body_id", m.body_p);
  SPHFEM_CHECK(m.interface_p.empty() || m.interface_p.size() == p, "there are ",
               m.interface_p.size(), " interface flags for ", p, " particles");
  write_array(particles, "interface",
              m.interface_p.empty() ? std::vector<Index>(p, 0) : m.interface_p);
}

// Background nodes ascending and in range, one positive finite h and spacing each.
void check_coupling(const Model& m, const std::string& where) {
  const std::size_t b = m.background_nodes.size();
  SPHFEM_CHECK(m.h_background.size() == b, where, "h has ", m.h_background.size(), " entries for ",
               b, " background nodes");
  SPHFEM_CHECK(m.spacing_background.size() == b, where, "spacing has ", m.spacing_background.size(),
               " entries for ", b, " background nodes");
  check_indices(m.background_nodes, m.x_n.size(), where + "background_nodes");
  for (std::size_t i = 1; i < b; ++i)
    SPHFEM_CHECK(m.background_nodes[i - 1] < m.background_nodes[i], where,
                 "background_nodes is not ascending at index ", i, " (", m.background_nodes[i - 1],
                 " then ", m.background_nodes[i], ")");
  for (const auto& [values, name] :
       {std::pair{&m.h_background, "h"}, std::pair{&m.spacing_background, "spacing"}})
    for (std::size_t i = 0; i < b; ++i)
      SPHFEM_CHECK(std::isfinite((*values)[i]) && (*values)[i] > 0, where, name, " holds ",
                   (*values)[i], " at index ", i, " (expected > 0)");
}

void write_coupling(const H5::H5File& file, const Model& m) {
  check_coupling(m, "coupling/");
  const H5::Group coupling = file.createGroup("coupling");
  write_array(coupling, "background_nodes", m.background_nodes);
  write_attribute(write_array(coupling, "h", m.h_background), "units", "m");
  write_attribute(write_array(coupling, "spacing", m.spacing_background), "units", "m");
}

// /particle_faces/<body>/<face>/{index, area} and the face group's attribute normal.
void write_particle_faces(const H5::H5File& file, const Model& m) {
  const H5::Group faces = file.createGroup("particle_faces");
  for (const auto& [name, face] : m.particle_faces) {
    check_set_name(name);
    const std::string what = "particle face '" + name + "'";
    SPHFEM_CHECK(face.area.size() == face.particles.size(), what, " has ", face.area.size(),
                 " areas for ", face.particles.size(), " particles");
    check_indices(face.particles, m.x_p.size(), what);
    write_array(faces, name + "/index", face.particles);
    write_attribute(write_array(faces, name + "/area", face.area), "units", "m^2");
    const hsize_t three = 3;
    faces.openGroup(name)
        .createAttribute("normal", H5Type<double>::file(), H5::DataSpace(1, &three))
        .write(H5Type<double>::memory(), face.normal.data());
  }
}

void write_model(const H5::H5File& file, const Model& m) {
  SPHFEM_CHECK(m.body_n.size() == m.x_n.size(), "node body ids do not match the nodes");
  SPHFEM_CHECK(m.body_e.size() == m.hex_e.size(), "element body ids do not match the elements");
  SPHFEM_CHECK(m.spacing_b.empty() || m.spacing_b.size() == m.body_names.size(), "there are ",
               m.spacing_b.size(), " body spacings for ", m.body_names.size(), " bodies");
  write_attribute(file, "format", format_name);
  write_attribute(file, "format_version", format_version);
  write_attribute(file, "generator", std::string("sphfem ") + SPHFEM_VERSION);
  write_attribute(file, "units", "SI (m, kg, s)");
  write_attribute(file, "signature", m.signature);

  const H5::Group bodies = file.createGroup("bodies");
  write_strings(bodies, "names", m.body_names);
  const std::vector<double> spacing =
      m.spacing_b.empty() ? std::vector<double>(m.body_names.size(), 0.0) : m.spacing_b;
  write_attribute(write_array(bodies, "spacing", spacing), "units", "m");
  const H5::Group nodes = file.createGroup("nodes");
  write_attribute(write_array(nodes, "x", flatten(m.x_n), 3), "units", "m");
  write_array(nodes, "body_id", m.body_n);
  const H5::Group elements = file.createGroup("elements");
  write_attribute(write_array(elements, "hex", flatten(m.hex_e), 8), "node_order",
                  "gmsh hexahedron");
  write_array(elements, "body_id", m.body_e);
  write_sets(file.createGroup("node_sets"), m.node_sets, 0);
  write_sets(file.createGroup("face_sets"), m.face_sets, 4);
  write_particles(file, m);
  write_particle_faces(file, m);
  write_coupling(file, m);
}

// ---- reading ------------------------------------------------------------------------------

std::string read_string_attribute(const H5::H5Object& object, const std::string& name) {
  SPHFEM_CHECK(object.attrExists(name), "missing attribute '", name, "'");
  const H5::Attribute attribute = object.openAttribute(name);
  SPHFEM_CHECK(attribute.getTypeClass() == H5T_STRING, "attribute '", name, "' is not a string");
  const H5::StrType type = attribute.getStrType();
  SPHFEM_CHECK(!type.isVariableStr(), "attribute '", name,
               "' is a variable-length string: a model.h5 of an older sphfem (format 1); "
               "re-mesh with `sphfem mesh`");
  const std::size_t bytes = type.getSize();
  SPHFEM_CHECK(bytes <= longest_string && attribute.getSpace().getSimpleExtentNpoints() == 1,
               "attribute '", name, "' is not one string of at most ", longest_string, " bytes");
  std::vector<char> value(bytes, '\0');
  attribute.read(type, value.data());
  return {value.data(), strnlen(value.data(), bytes)};
}

int read_int_attribute(const H5::H5Object& object, const std::string& name) {
  SPHFEM_CHECK(object.attrExists(name), "missing attribute '", name, "'");
  const H5::Attribute attribute = object.openAttribute(name);
  SPHFEM_CHECK(attribute.getTypeClass() == H5T_INTEGER &&
                   attribute.getSpace().getSimpleExtentNpoints() == 1,
               "attribute '", name, "' is not an integer");
  int value = 0;
  attribute.read(H5::PredType::NATIVE_INT, &value);
  return value;
}

// Opens `path` (relative, '/'-separated) below `parent`, checking each link exists.
H5::DataSet open_dataset(const H5::Group& parent, const std::string& path) {
  for (std::size_t slash = path.find('/'); slash != std::string::npos;
       slash = path.find('/', slash + 1))
    SPHFEM_CHECK(parent.nameExists(path.substr(0, slash)), "missing group '", path.substr(0, slash),
                 "'");
  SPHFEM_CHECK(parent.nameExists(path) && parent.childObjType(path) == H5O_TYPE_DATASET,
               "missing dataset '", path, "'");
  return parent.openDataSet(path);
}

// Reads a rows × cols dataset (1-D when cols == 0), checking its type class and shape.
// A corrupt header may claim any extent; data cannot expand beyond what its stored bytes can
// (deflate at most 1 032:1), nor be stored in more bytes than the file has. Checked before
// anything is allocated for it.
void check_stored(const H5::DataSet& dataset, const std::string& path, double bytes) {
  const hid_t file = H5Iget_file_id(dataset.getId());
  hsize_t file_bytes = 0;
  H5Fget_filesize(file, &file_bytes);
  H5Fclose(file);
  // The storage a header claims cannot exceed the file either.
  const double stored =
      static_cast<double>(std::min<hsize_t>(dataset.getStorageSize(), file_bytes));
  SPHFEM_CHECK(bytes <= 1100.0 * stored + 4096.0, "dataset '", path, "' claims ", bytes,
               " bytes but stores ", stored, ": the file is corrupt");
}

template <class T>
std::vector<T> read_array(const H5::Group& parent, const std::string& path, hsize_t cols = 0) {
  const H5::DataSet dataset = open_dataset(parent, path);
  SPHFEM_CHECK(dataset.getTypeClass() == H5Type<T>::type_class, "dataset '", path,
               "' has the wrong type (expected ",
               H5Type<T>::type_class == H5T_FLOAT ? "float" : "integer", ")");
  const H5::DataSpace space = dataset.getSpace();
  const int rank = cols == 0 ? 1 : 2;
  std::array<hsize_t, 2> dims{0, 0};
  SPHFEM_CHECK(space.getSimpleExtentNdims() == rank, "dataset '", path, "' must have rank ", rank);
  space.getSimpleExtentDims(dims.data());
  SPHFEM_CHECK(cols == 0 || dims[1] == cols, "dataset '", path, "' must have ", cols,
               " columns, not ", dims[1]);
  // HDF5 converts through a buffer of the file's element size: a corrupt type may claim any.
  const std::size_t file_element = dataset.getDataType().getSize();
  SPHFEM_CHECK(file_element <= 16, "dataset '", path, "' has elements of ", file_element,
               " bytes (at most 16 for a number)");
  check_stored(dataset, path,
               static_cast<double>(dims[0]) * std::max<hsize_t>(cols, 1) *
                   std::max(file_element, sizeof(T)));
  std::vector<T> values(dims[0] * std::max<hsize_t>(cols, 1));
  if (!values.empty())
    dataset.read(values.data(), H5Type<T>::memory());
  return values;
}

template <std::size_t C>
std::vector<std::array<Index, C>> read_rows(const H5::Group& parent, const std::string& path) {
  const std::vector<Index> flat = read_array<Index>(parent, path, C);
  std::vector<std::array<Index, C>> rows(flat.size() / C);
  for (std::size_t r = 0; r < rows.size(); ++r)
    std::copy_n(flat.begin() + static_cast<std::ptrdiff_t>(C * r), C, rows[r].begin());
  return rows;
}

std::vector<Vec3> read_points(const H5::Group& parent, const std::string& path) {
  const std::vector<double> flat = read_array<double>(parent, path, 3);
  std::vector<Vec3> points(flat.size() / 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = Vec3(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return points;
}

std::vector<std::string> read_strings(const H5::Group& parent, const std::string& path) {
  const H5::DataSet dataset = open_dataset(parent, path);
  const H5::DataSpace space = dataset.getSpace();
  SPHFEM_CHECK(dataset.getTypeClass() == H5T_STRING && space.getSimpleExtentNdims() == 1,
               "dataset '", path, "' must be a list of strings");
  const H5::StrType type = dataset.getStrType();
  SPHFEM_CHECK(!type.isVariableStr(), "dataset '", path,
               "' holds variable-length strings: a model.h5 of an older sphfem (format 1); "
               "re-mesh with `sphfem mesh`");
  const std::size_t width = type.getSize();
  const auto n = static_cast<std::size_t>(space.getSimpleExtentNpoints());
  SPHFEM_CHECK(width <= longest_string, "dataset '", path, "' holds strings of ", width,
               " bytes (at most ", longest_string, ")");
  check_stored(dataset, path, static_cast<double>(n) * width);
  std::vector<char> packed(n * width, '\0');
  if (n > 0)
    dataset.read(packed.data(), type);
  std::vector<std::string> strings;
  for (std::size_t i = 0; i < n; ++i) {
    const char* s = packed.data() + i * width;
    strings.emplace_back(s, strnlen(s, width));
  }
  return strings;
}

// Dataset paths below `group`, relative to it, depth-first in name order.
void list_datasets(const H5::Group& group, const std::string& prefix,
                   std::vector<std::string>& paths) {
  for (hsize_t i = 0; i < group.getNumObjs(); ++i) {
    const std::string name = group.getObjnameByIdx(i);
    const H5O_type_t type = group.childObjType(name);
    if (type == H5O_TYPE_GROUP)
      list_datasets(group.openGroup(name), prefix + name + "/", paths);
    else if (type == H5O_TYPE_DATASET)
      paths.push_back(prefix + name);
  }
}

std::vector<std::string> set_names(const H5::Group& root, const std::string& group) {
  SPHFEM_CHECK(root.nameExists(group), "missing group '", group, "'");
  std::vector<std::string> names;
  list_datasets(root.openGroup(group), "", names);
  return names;
}

void check_header(const H5::H5File& file) {
  const std::string format = read_string_attribute(file, "format");
  SPHFEM_CHECK(format == format_name, "not an sphfem model (format '", format, "', expected '",
               format_name, "')");
  const int version = read_int_attribute(file, "format_version");
  SPHFEM_CHECK(version == format_version, "format_version ", version,
               " is not supported (this build reads version ", format_version, ")");
}

// Checks that every value is finite and, unless `zero_ok`, positive.
void check_values(const std::vector<double>& values, const std::string& what, bool zero_ok) {
  for (std::size_t i = 0; i < values.size(); ++i)
    SPHFEM_CHECK(std::isfinite(values[i]) && (values[i] > 0 || (zero_ok && values[i] == 0)), what,
                 " holds ", values[i], " at index ", i, " (expected ", zero_ok ? ">= 0" : "> 0",
                 ")");
}

// /bodies/spacing, or 0 for every body in a file written before it existed.
std::vector<double> read_spacing(const H5::H5File& file, std::size_t bodies) {
  if (!file.nameExists("bodies/spacing"))
    return std::vector<double>(bodies, 0.0);
  std::vector<double> spacing = read_array<double>(file, "bodies/spacing");
  SPHFEM_CHECK(spacing.size() == bodies, "bodies/spacing has ", spacing.size(), " entries for ",
               bodies, " bodies");
  check_values(spacing, "bodies/spacing", true);
  return spacing;
}

// /particles, or none in a file written before it existed.
void read_particles(const H5::H5File& file, Model& m) {
  if (!file.nameExists("particles"))
    return;
  m.x_p = read_points(file, "particles/x");
  m.m_p = read_array<double>(file, "particles/mass");
  m.rho_p = read_array<double>(file, "particles/density");
  m.h_p = read_array<double>(file, "particles/h");
  m.body_p = read_array<Index>(file, "particles/body_id");
  const std::size_t p = m.x_p.size();
  for (const auto& [name, size] : {std::pair{"particles/mass", m.m_p.size()},
                                   {"particles/density", m.rho_p.size()},
                                   {"particles/h", m.h_p.size()},
                                   {"particles/body_id", m.body_p.size()}})
    SPHFEM_CHECK(size == p, name, " has ", size, " entries for ", p, " particles");
  for (std::size_t i = 0; i < p; ++i)
    SPHFEM_CHECK(m.x_p[i].allFinite(), "particles/x holds a non-finite position at index ", i);
  check_values(m.m_p, "particles/mass", false);
  check_values(m.rho_p, "particles/density", false);
  check_values(m.h_p, "particles/h", false);
  check_indices(m.body_p, m.body_names.size(), "particles/body_id");
  for (std::size_t i = 0; i < p; ++i)
    SPHFEM_CHECK(m.spacing_b[m.body_p[i]] > 0, "particles/body_id holds body ", m.body_p[i], " ('",
                 m.body_names[m.body_p[i]], "', spacing 0: not an SPH body) at index ", i);
}

// /particles/interface, or 0 for every particle in a file written before it existed.
void read_interface(const H5::H5File& file, Model& m) {
  const std::size_t p = m.x_p.size();
  if (!file.nameExists("particles") || !file.openGroup("particles").nameExists("interface")) {
    m.interface_p.assign(p, 0);
    return;
  }
  m.interface_p = read_array<Index>(file, "particles/interface");
  SPHFEM_CHECK(m.interface_p.size() == p, "particles/interface has ", m.interface_p.size(),
               " entries for ", p, " particles");
  for (std::size_t i = 0; i < p; ++i)
    SPHFEM_CHECK(m.interface_p[i] == 0 || m.interface_p[i] == 1, "particles/interface holds ",
                 m.interface_p[i], " at index ", i, " (expected 0 or 1)");
}

// /coupling, or no background particles in a file written before it existed. Needs the nodes.
void read_coupling(const H5::H5File& file, Model& m) {
  if (!file.nameExists("coupling"))
    return;
  m.background_nodes = read_array<Index>(file, "coupling/background_nodes");
  m.h_background = read_array<double>(file, "coupling/h");
  m.spacing_background = read_array<double>(file, "coupling/spacing");
  check_coupling(m, "coupling/");
}

// Paths (relative to `group`) of the particle faces below it: groups holding a dataset, or
// nothing at all (then reported as missing their datasets); other groups are searched.
void list_particle_faces(const H5::Group& group, const std::string& prefix,
                         std::vector<std::string>& paths) {
  for (hsize_t i = 0; i < group.getNumObjs(); ++i) {
    const std::string name = group.getObjnameByIdx(i);
    if (group.childObjType(name) != H5O_TYPE_GROUP)
      continue;
    const H5::Group child = group.openGroup(name);
    bool face = child.getNumObjs() == 0;
    for (hsize_t j = 0; j < child.getNumObjs() && !face; ++j)
      face = child.childObjType(child.getObjnameByIdx(j)) == H5O_TYPE_DATASET;
    if (face)
      paths.push_back(prefix + name);
    else
      list_particle_faces(child, prefix + name + "/", paths);
  }
}

Vec3 read_unit_vector_attribute(const H5::H5Object& object, const std::string& name,
                                const std::string& where) {
  SPHFEM_CHECK(object.attrExists(name), "missing attribute '", name, "' of ", where);
  const H5::Attribute attribute = object.openAttribute(name);
  SPHFEM_CHECK(attribute.getTypeClass() == H5T_FLOAT &&
                   attribute.getSpace().getSimpleExtentNpoints() == 3,
               "attribute '", name, "' of ", where, " is not 3 floating-point numbers");
  Vec3 v;
  attribute.read(H5Type<double>::memory(), v.data());
  SPHFEM_CHECK(v.allFinite() && std::abs(v.norm() - 1) <= 1e-9, "attribute '", name, "' of ", where,
               " is not a unit vector: (", v.x(), ", ", v.y(), ", ", v.z(), ")");
  return v;
}

// /particle_faces, or none in a file written before it existed. Needs the particles.
void read_particle_faces(const H5::H5File& file, Model& m) {
  if (!file.nameExists("particle_faces"))
    return;
  std::vector<std::string> names;
  list_particle_faces(file.openGroup("particle_faces"), "", names);
  for (const std::string& name : names) {
    const std::string path = "particle_faces/" + name;
    ParticleFace face;
    face.particles = read_array<Index>(file, path + "/index");
    face.area = read_array<double>(file, path + "/area");
    SPHFEM_CHECK(face.area.size() == face.particles.size(), path, "/area has ", face.area.size(),
                 " entries for ", face.particles.size(), " particles");
    check_indices(face.particles, m.x_p.size(), path + "/index");
    check_values(face.area, path + "/area", false);
    face.normal = read_unit_vector_attribute(file.openGroup(path), "normal", path);
    m.particle_faces[name] = std::move(face);
  }
}

Model read_model(const H5::H5File& file) {
  check_header(file);
  Model m;
  m.signature = read_string_attribute(file, "signature");
  m.body_names = read_strings(file, "bodies/names");
  m.spacing_b = read_spacing(file, m.body_names.size());
  m.x_n = read_points(file, "nodes/x");
  m.body_n = read_array<Index>(file, "nodes/body_id");
  m.hex_e = read_rows<8>(file, "elements/hex");
  m.body_e = read_array<Index>(file, "elements/body_id");
  SPHFEM_CHECK(m.body_n.size() == m.x_n.size(), "nodes/body_id has ", m.body_n.size(),
               " entries for ", m.x_n.size(), " nodes");
  SPHFEM_CHECK(m.body_e.size() == m.hex_e.size(), "elements/body_id has ", m.body_e.size(),
               " entries for ", m.hex_e.size(), " elements");
  check_indices(m.body_n, m.body_names.size(), "nodes/body_id");
  check_indices(m.body_e, m.body_names.size(), "elements/body_id");
  const std::size_t n = m.x_n.size();
  for (const Hex& hex : m.hex_e)
    check_indices(hex, n, "elements/hex");
  for (const std::string& name : set_names(file, "node_sets")) {
    m.node_sets[name] = read_array<Index>(file, "node_sets/" + name);
    check_indices(m.node_sets[name], n, "node set '" + name + "'");
  }
  for (const std::string& name : set_names(file, "face_sets")) {
    m.face_sets[name] = read_rows<4>(file, "face_sets/" + name);
    for (const Quad& q : m.face_sets[name])
      check_indices(q, n, "face set '" + name + "'");
  }
  read_particles(file, m);
  read_interface(file, m);
  read_particle_faces(file, m);
  read_coupling(file, m);
  return m;
}

} // namespace

void write_model_h5(const Model& m, const fs::path& file) {
  const Hdf5Errors errors;
  try {
    write_atomically(file, [&](const fs::path& temporary) {
      H5::H5File h5(temporary.string(), H5F_ACC_TRUNC, sealed_file_properties());
      write_model(h5, m);
      h5.close();
      seal_h5_file(temporary);
    });
  } catch (const H5::Exception& e) {
    throw Error(detail::concat("cannot write model file ", file, ": HDF5: ", errors.describe(e)));
  } catch (const Error& e) {
    throw Error(detail::concat("cannot write model file ", file, ": ", e.what()));
  }
}

Model read_model_h5(const fs::path& file) {
  const Hdf5Errors errors;
  try {
    check_h5_seal(file);
    return read_model(H5::H5File(file.string(), H5F_ACC_RDONLY));
  } catch (const H5::Exception& e) {
    throw Error(detail::concat("model file ", file, ": HDF5 cannot read it: ", errors.describe(e)));
  } catch (const Error& e) {
    throw Error(detail::concat("model file ", file, ": ", e.what()));
  }
}

} // namespace sphfem
