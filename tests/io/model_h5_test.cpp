// Tests of solver/io/model_h5.hpp and model_vtu.hpp: exact round trips of model.h5 (with and
// without SPH particles and their faces), clear errors (naming the file) for damaged or foreign
// files, files from before particles, particle faces or coupling tags existed, and model.vtu and
// model_particles.vtu read back with VTK.
#include "solver/io/model_h5.hpp"
#include "solver/io/model_vtu.hpp"
#include "solver/io/sealed_h5.hpp"

#include "solver/core/error.hpp"

#include <H5Cpp.h>
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>

namespace sphfem {
namespace {

namespace fs = std::filesystem;

// A structured nx × ny × nz hex grid with irrational coordinates, split into two bodies at
// half height, with named node and face sets on its bottom and right faces, and background
// particles on every third node (1, 4, 7, …) with irrational h and spacing.
Model grid_model(int nx, int ny, int nz) {
  Model m;
  m.body_names = {"bar", "anvil"};
  m.spacing_b = {0, 0};
  m.signature = "sphfem-mesh 1\nbody bar method=fem box min=0,0,0 max=1,1,1 element_size=0.1\n";
  const auto node = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        m.x_n.emplace_back(i * std::sqrt(2.0) / 7, j * std::numbers::pi / 11, k / 3.0);
        m.body_n.push_back(2 * k < nz ? 0 : 1);
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        m.hex_e.push_back({node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k),
                           node(i, j + 1, k), node(i, j, k + 1), node(i + 1, j, k + 1),
                           node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)});
        m.body_e.push_back(2 * k < nz ? 0 : 1);
      }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      m.face_sets["bar/zmin"].push_back(
          {node(i, j, 0), node(i, j + 1, 0), node(i + 1, j + 1, 0), node(i + 1, j, 0)});
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      m.face_sets["anvil/xmax"].push_back(
          {node(nx, j, k), node(nx, j + 1, k), node(nx, j + 1, k + 1), node(nx, j, k + 1)});
  for (const auto& [name, quads] : m.face_sets) {
    auto& nodes = m.node_sets[name];
    for (const Quad& q : quads)
      nodes.insert(nodes.end(), q.begin(), q.end());
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  }
  for (Index n = 1; n < m.node_count(); n += 3) {
    m.background_nodes.push_back(n);
    m.h_background.push_back(1e-3 * (1 + std::sqrt(n) / 10));
    m.spacing_background.push_back(std::numbers::pi * 1e-3 / (1 + n % 2));
  }
  return m;
}

// grid_model with a third body "ball" of `count` SPH particles: irrational positions, masses,
// densities and smoothing lengths that differ per particle; and two particle faces, "ball/zmin"
// (every other particle, normal −z) and "ball/side" (particles 1, 4, 7, …, an oblique normal;
// empty when count = 1), with irrational areas. Particles 0, 3, 6, … are at the interface.
Model particle_model(int count) {
  Model m = grid_model(3, 2, 2);
  m.body_names.push_back("ball");
  m.spacing_b.push_back(std::numbers::pi * 1e-3);
  for (int i = 0; i < count; ++i) {
    const double t = i + 1;
    m.x_p.emplace_back(std::sqrt(t) / 13, std::cbrt(t) / 7, std::log(t + 1) / 3);
    m.m_p.push_back(1e-6 * (1 + std::sin(t) / 2));
    m.rho_p.push_back(7830 + std::cos(t));
    m.h_p.push_back(1.2e-3 * (1 + 1 / t));
    m.body_p.push_back(2);
    m.interface_p.push_back(i % 3 == 0 ? 1 : 0);
  }
  ParticleFace& bottom = m.particle_faces["ball/zmin"];
  bottom.normal = -Vec3::UnitZ();
  ParticleFace& side = m.particle_faces["ball/side"];
  side.normal = Vec3(1, std::sqrt(2.0), -0.5).normalized();
  for (int i = 0; i < count; ++i) {
    ParticleFace& face = i % 2 == 0 ? bottom : side;
    if (i % 2 == 0 || i % 3 == 1) {
      face.particles.push_back(i);
      face.area.push_back(1e-6 * (1 + std::sqrt(i + 2.0) / 5));
    }
  }
  return m;
}

class ModelFiles : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sphfem_model_h5_test_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path path(const std::string& name) const { return dir_ / name; }

  // Writes a small model to `name`, lets `edit` damage it through HDF5 and seals it again, so
  // that what is tested is the reader's own check behind the seal.
  fs::path damaged(const std::string& name, const std::function<void(H5::H5File&)>& edit) const {
    const fs::path file = path(name);
    write_model_h5(grid_model(3, 2, 2), file);
    {
      H5::H5File h5(file.string(), H5F_ACC_RDWR);
      edit(h5);
    }
    seal_h5_file(file);
    return file;
  }

  static void expect_read_error(const fs::path& file, const std::string& fragment) {
    try {
      read_model_h5(file);
      ADD_FAILURE() << "no error reading " << file;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(file.string()), std::string::npos) << message;
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
    }
  }

  fs::path dir_;
};

void expect_same(const Model& a, const Model& b) {
  EXPECT_EQ(a.body_names, b.body_names);
  EXPECT_EQ(a.x_n, b.x_n); // bit for bit
  EXPECT_EQ(a.body_n, b.body_n);
  EXPECT_EQ(a.hex_e, b.hex_e);
  EXPECT_EQ(a.body_e, b.body_e);
  EXPECT_EQ(a.node_sets, b.node_sets);
  EXPECT_EQ(a.face_sets, b.face_sets);
  EXPECT_EQ(a.signature, b.signature);
  EXPECT_EQ(a.spacing_b, b.spacing_b);
  EXPECT_EQ(a.x_p, b.x_p); // bit for bit
  EXPECT_EQ(a.m_p, b.m_p);
  EXPECT_EQ(a.rho_p, b.rho_p);
  EXPECT_EQ(a.h_p, b.h_p);
  EXPECT_EQ(a.body_p, b.body_p);
  EXPECT_EQ(a.background_nodes, b.background_nodes);
  EXPECT_EQ(a.h_background, b.h_background); // bit for bit
  EXPECT_EQ(a.spacing_background, b.spacing_background);
  EXPECT_EQ(a.interface_p, b.interface_p);
  ASSERT_EQ(a.particle_faces.size(), b.particle_faces.size());
  for (const auto& [name, face] : a.particle_faces) {
    ASSERT_TRUE(b.particle_faces.contains(name)) << name;
    const ParticleFace& other = b.particle_faces.at(name);
    EXPECT_EQ(face.particles, other.particles) << name;
    EXPECT_EQ(face.area, other.area) << name; // bit for bit
    EXPECT_EQ(face.normal, other.normal) << name;
  }
}

// ---- model.h5 -------------------------------------------------------------------------------

TEST_F(ModelFiles, RoundTripsExactly) {
  const Model m = grid_model(30, 30, 20); // 18000 hexes: exercises chunked, compressed datasets
  const fs::path file = path("model.h5");
  write_model_h5(m, file);
  EXPECT_FALSE(fs::exists(path("model.h5.tmp")));
  expect_same(read_model_h5(file), m);
}

TEST_F(ModelFiles, EmptyModelRoundTrips) {
  Model m;
  m.signature = "";
  write_model_h5(m, path("empty.h5"));
  expect_same(read_model_h5(path("empty.h5")), m);
}

TEST_F(ModelFiles, RoundTripsParticlesExactly) {
  for (const int count : {1, 20000}) { // 20000: chunked, compressed datasets
    const Model m = particle_model(count);
    const fs::path file = path("particles.h5");
    write_model_h5(m, file);
    expect_same(read_model_h5(file), m);
  }
}

// Large faces (chunked, compressed), empty faces, and names nested deeper than <body>/<face>.
TEST_F(ModelFiles, RoundTripsParticleFacesExactly) {
  Model m = particle_model(40000); // ball/zmin: 20000 particles
  ASSERT_GT(m.particle_faces.at("ball/zmin").particles.size(), 16384u);
  m.particle_faces["ball/layer/deep"] = {{7, 3}, {2.5e-7, 1e-7}, Vec3::UnitX()};
  m.particle_faces["ball/none"] = {{}, {}, Vec3::UnitY()};
  const fs::path file = path("faces.h5");
  write_model_h5(m, file);
  const Model read = read_model_h5(file);
  EXPECT_EQ(read.particle_faces.size(), 4u);
  expect_same(read, m);
  // Small models too (ball/side is empty with one particle).
  for (const int count : {1, 5}) {
    write_model_h5(particle_model(count), file);
    expect_same(read_model_h5(file), particle_model(count));
  }
}

TEST_F(ModelFiles, ParticleFacesAreStoredAsDocumented) {
  const Model m = particle_model(5);
  write_model_h5(m, path("model.h5"));
  const H5::H5File h5(path("model.h5").string(), H5F_ACC_RDONLY);
  const H5::Group face = h5.openGroup("particle_faces/ball/zmin");
  std::vector<int> index(3);
  std::vector<double> area(3);
  ASSERT_EQ(face.openDataSet("index").getSpace().getSimpleExtentNpoints(), 3);
  face.openDataSet("index").read(index.data(), H5::PredType::NATIVE_INT);
  face.openDataSet("area").read(area.data(), H5::PredType::NATIVE_DOUBLE);
  EXPECT_EQ(index, (std::vector<int>{0, 2, 4}));
  EXPECT_EQ(area, m.particle_faces.at("ball/zmin").area);
  std::string units;
  const H5::Attribute a = face.openDataSet("area").openAttribute("units");
  a.read(a.getStrType(), units);
  EXPECT_EQ(units, "m^2");
  const H5::Attribute normal = face.openAttribute("normal");
  ASSERT_EQ(normal.getSpace().getSimpleExtentNpoints(), 3);
  Vec3 n;
  normal.read(H5::PredType::NATIVE_DOUBLE, n.data());
  EXPECT_EQ(n, Vec3(0, 0, -1));
}

// A file written before particle faces existed reads as a model without them.
TEST_F(ModelFiles, FileWithoutParticleFacesReadsAsNone) {
  const fs::path file = path("old.h5");
  write_model_h5(particle_model(5), file);
  H5::H5File(file.string(), H5F_ACC_RDWR).unlink("particle_faces");
  seal_h5_file(file);
  const Model m = read_model_h5(file);
  EXPECT_EQ(m.particle_count(), 5);
  EXPECT_TRUE(m.particle_faces.empty());
}

TEST_F(ModelFiles, BadParticleFacesAreNotWritten) {
  const auto expect_write_error = [&](const Model& m, const std::string& fragment) {
    try {
      write_model_h5(m, path("model.h5"));
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  Model m = particle_model(5);
  m.particle_faces.at("ball/zmin").area.pop_back();
  expect_write_error(m, "particle face 'ball/zmin' has 2 areas for 3 particles");
  m = particle_model(5);
  m.particle_faces.at("ball/side").particles.back() = 5;
  expect_write_error(m, "particle face 'ball/side' holds index 5 outside [0, 5)");
  m = particle_model(5);
  m.particle_faces["/ball"] = {};
  expect_write_error(m, "set name '/ball' cannot be stored");
}

TEST_F(ModelFiles, ParticleDatasetsCarryUnits) {
  write_model_h5(particle_model(3), path("model.h5"));
  const H5::H5File h5(path("model.h5").string(), H5F_ACC_RDONLY);
  const auto units = [&](const std::string& dataset) {
    std::string s;
    const H5::Attribute a = h5.openDataSet(dataset).openAttribute("units");
    a.read(a.getStrType(), s);
    return s;
  };
  EXPECT_EQ(units("particles/x"), "m");
  EXPECT_EQ(units("particles/mass"), "kg");
  EXPECT_EQ(units("particles/density"), "kg/m^3");
  EXPECT_EQ(units("particles/h"), "m");
  EXPECT_EQ(units("bodies/spacing"), "m");
  EXPECT_TRUE(h5.nameExists("particles/body_id"));
}

// Models built without spacings (FE only) are written with spacing 0 for every body.
TEST_F(ModelFiles, EmptySpacingIsWrittenAsZeros) {
  Model m = grid_model(2, 1, 2);
  m.spacing_b.clear();
  write_model_h5(m, path("model.h5"));
  EXPECT_EQ(read_model_h5(path("model.h5")).spacing_b, (std::vector<double>{0, 0}));
}

// A file written before SPH particles existed has neither /particles nor /bodies/spacing.
TEST_F(ModelFiles, FileWithoutParticlesReadsAsNoParticles) {
  const fs::path file = damaged("old.h5", [](H5::H5File& h5) {
    h5.unlink("particles");
    h5.unlink("particle_faces");
    h5.unlink("bodies/spacing");
  });
  const Model m = read_model_h5(file);
  expect_same(m, grid_model(3, 2, 2));
  EXPECT_EQ(m.particle_count(), 0);
  EXPECT_EQ(m.spacing_b, (std::vector<double>{0, 0}));
}

TEST_F(ModelFiles, MismatchedParticleArraysAreNotWritten) {
  Model m = particle_model(4);
  m.h_p.pop_back();
  EXPECT_THROW(write_model_h5(m, path("model.h5")), Error);
  m = particle_model(4);
  m.spacing_b.pop_back();
  EXPECT_THROW(write_model_h5(m, path("model.h5")), Error);
}

// ---- coupling tags ----

TEST_F(ModelFiles, CouplingIsStoredAsDocumented) {
  const Model m = particle_model(5); // background nodes 1, 4, …, 34 of 36
  write_model_h5(m, path("model.h5"));
  const H5::H5File h5(path("model.h5").string(), H5F_ACC_RDONLY);
  const auto read_ints = [&](const std::string& name) {
    const H5::DataSet d = h5.openDataSet(name);
    EXPECT_EQ(d.getTypeClass(), H5T_INTEGER) << name;
    std::vector<int> values(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
    d.read(values.data(), H5::PredType::NATIVE_INT);
    return values;
  };
  const auto read_doubles = [&](const std::string& name) {
    const H5::DataSet d = h5.openDataSet(name);
    std::vector<double> values(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
    d.read(values.data(), H5::PredType::NATIVE_DOUBLE);
    return values;
  };
  const auto units = [&](const std::string& name) {
    std::string text;
    const H5::Attribute a = h5.openDataSet(name).openAttribute("units");
    a.read(a.getStrType(), text);
    return text;
  };
  EXPECT_EQ(read_ints("coupling/background_nodes"), m.background_nodes);
  EXPECT_EQ(m.background_nodes.size(), 12u);
  EXPECT_EQ(read_doubles("coupling/h"), m.h_background);
  EXPECT_EQ(read_doubles("coupling/spacing"), m.spacing_background);
  EXPECT_EQ(units("coupling/h"), "m");
  EXPECT_EQ(units("coupling/spacing"), "m");
  EXPECT_EQ(read_ints("particles/interface"), (std::vector<int>{1, 0, 0, 1, 0}));
}

// An uncoupled model: no background nodes (empty datasets), interface 0 everywhere.
TEST_F(ModelFiles, UncoupledModelRoundTrips) {
  Model m = particle_model(4);
  m.background_nodes.clear();
  m.h_background.clear();
  m.spacing_background.clear();
  m.interface_p.assign(4, 0);
  write_model_h5(m, path("model.h5"));
  expect_same(read_model_h5(path("model.h5")), m);
  m.interface_p.clear(); // written as zeros
  write_model_h5(m, path("model.h5"));
  EXPECT_EQ(read_model_h5(path("model.h5")).interface_p, (std::vector<int>(4, 0)));
}

// A file written before coupling tags existed has neither /coupling nor /particles/interface:
// it reads as uncoupled, which is what its case (which could not name couplings) makes.
TEST_F(ModelFiles, FileWithoutCouplingReadsAsUncoupled) {
  const fs::path file = path("old.h5");
  write_model_h5(particle_model(5), file);
  {
    H5::H5File h5(file.string(), H5F_ACC_RDWR);
    h5.unlink("coupling");
    h5.unlink("particles/interface");
  }
  seal_h5_file(file);
  const Model m = read_model_h5(file);
  EXPECT_EQ(m.particle_count(), 5);
  EXPECT_TRUE(m.background_nodes.empty());
  EXPECT_TRUE(m.h_background.empty());
  EXPECT_TRUE(m.spacing_background.empty());
  EXPECT_EQ(m.interface_p, (std::vector<int>(5, 0)));
}

TEST_F(ModelFiles, BadCouplingIsNotWritten) {
  const auto expect_write_error = [&](const Model& m, const std::string& fragment) {
    try {
      write_model_h5(m, path("model.h5"));
      ADD_FAILURE() << "no error for " << fragment;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(path("model.h5")));
  };
  Model m = particle_model(5);
  m.h_background.pop_back();
  expect_write_error(m, "coupling/h has 11 entries for 12 background nodes");
  m = particle_model(5);
  m.spacing_background.push_back(1e-3);
  expect_write_error(m, "coupling/spacing has 13 entries for 12 background nodes");
  m = particle_model(5);
  m.background_nodes.back() = 36;
  expect_write_error(m, "coupling/background_nodes holds index 36 outside [0, 36)");
  m = particle_model(5);
  std::swap(m.background_nodes[2], m.background_nodes[3]);
  expect_write_error(m, "coupling/background_nodes is not ascending at index 3 (10 then 7)");
  m = particle_model(5);
  m.background_nodes[1] = m.background_nodes[0];
  expect_write_error(m, "not ascending at index 1 (1 then 1)");
  m = particle_model(5);
  m.h_background[4] = 0;
  expect_write_error(m, "coupling/h holds 0 at index 4 (expected > 0)");
  m = particle_model(5);
  m.spacing_background[0] = std::numeric_limits<double>::quiet_NaN();
  expect_write_error(m, "coupling/spacing holds nan at index 0");
  m = particle_model(5);
  m.interface_p.pop_back();
  expect_write_error(m, "there are 4 interface flags for 5 particles");
}

TEST_F(ModelFiles, OverwritesAnExistingFile) {
  const fs::path file = path("model.h5");
  write_model_h5(grid_model(2, 2, 2), file);
  const Model m = grid_model(3, 1, 2);
  write_model_h5(m, file);
  expect_same(read_model_h5(file), m);
}

TEST_F(ModelFiles, IsSelfDescribing) {
  const fs::path file = path("model.h5");
  write_model_h5(grid_model(2, 2, 2), file);
  const H5::H5File h5(file.string(), H5F_ACC_RDONLY);
  const auto text = [&](const H5::H5Object& o, const std::string& name) {
    std::string s;
    const H5::Attribute a = o.openAttribute(name);
    a.read(a.getStrType(), s);
    return s;
  };
  EXPECT_EQ(text(h5, "format"), "sphfem-model");
  EXPECT_EQ(text(h5, "units"), "SI (m, kg, s)");
  EXPECT_EQ(text(h5, "generator").rfind("sphfem ", 0), 0u);
  int version = 0;
  h5.openAttribute("format_version").read(H5::PredType::NATIVE_INT, &version);
  EXPECT_EQ(version, 3);
  EXPECT_EQ(text(h5.openDataSet("nodes/x"), "units"), "m");
  EXPECT_EQ(text(h5.openDataSet("elements/hex"), "node_order"), "gmsh hexahedron");
  EXPECT_TRUE(h5.nameExists("node_sets/bar/zmin"));
  EXPECT_TRUE(h5.nameExists("face_sets/anvil/xmax"));
}

TEST_F(ModelFiles, UnwritablePathIsAnError) {
  const fs::path file = path("no_such_dir") / "model.h5";
  try {
    write_model_h5(grid_model(1, 1, 1), file);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST_F(ModelFiles, WrongFormatVersionIsRejected) {
  const fs::path file = damaged("v4.h5", [](H5::H5File& h5) {
    h5.removeAttr("format_version");
    const int four = 4;
    h5.createAttribute("format_version", H5::PredType::STD_I32LE, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_INT, &four);
  });
  expect_read_error(file, "format_version 4 is not supported");
}

// Format 1 stored variable-length strings, through which a corrupt file could make HDF5
// allocate gigabytes before any check ran (found by fuzz/fuzz_model_h5): refused with advice.
TEST_F(ModelFiles, OlderFormatWithVariableLengthStringsIsRefused) {
  const fs::path file = damaged("v1.h5", [](H5::H5File& h5) {
    h5.removeAttr("format");
    const H5::StrType vlen(H5::PredType::C_S1, H5T_VARIABLE);
    h5.createAttribute("format", vlen, H5::DataSpace(H5S_SCALAR))
        .write(vlen, std::string("sphfem-model"));
  });
  expect_read_error(file, "attribute 'format' is a variable-length string: a model.h5 of an "
                          "older sphfem (format 1); re-mesh with `sphfem mesh`");
}

// A header claiming more data than the file stores is refused before anything is allocated.
TEST_F(ModelFiles, ExtentBeyondTheStoredDataIsRefused) {
  const fs::path file = damaged("huge.h5", [](H5::H5File& h5) {
    h5.unlink("nodes/x");
    const hsize_t dims[2] = {hsize_t(1) << 40, 3};
    h5.createDataSet("nodes/x", H5::PredType::IEEE_F64LE, H5::DataSpace(2, dims));
  });
  expect_read_error(file, "dataset 'nodes/x' claims 2.63883e+13 bytes but stores 0: the file is "
                          "corrupt");
}

// Element sizes no model writes: a 64-byte "number", a 100 000-byte name. (The same limit on
// attributes cannot be shown with a file HDF5 writes: it refuses attributes over 64 KiB.)
TEST_F(ModelFiles, ImplausibleElementSizesAreRefused) {
  const fs::path wide = damaged("wide.h5", [](H5::H5File& h5) {
    h5.unlink("nodes/body_id");
    const hsize_t n = 36;
    H5::IntType big(H5::PredType::STD_I32LE);
    big.setSize(64);
    h5.createDataSet("nodes/body_id", big, H5::DataSpace(1, &n));
  });
  expect_read_error(wide, "dataset 'nodes/body_id' has elements of 64 bytes (at most 16 for a "
                          "number)");
  const fs::path names = damaged("names.h5", [](H5::H5File& h5) {
    h5.unlink("bodies/names");
    const hsize_t n = 2;
    h5.createDataSet("bodies/names", H5::StrType(H5::PredType::C_S1, 100000), H5::DataSpace(1, &n));
  });
  expect_read_error(names, "dataset 'bodies/names' holds strings of 100000 bytes (at most 65536)");
}

TEST_F(ModelFiles, AnotherFormatIsRejected) {
  const fs::path file = damaged("other_format.h5", [](H5::H5File& h5) {
    h5.removeAttr("format");
    const std::string other = "sphfem-other";
    const H5::StrType type(H5::PredType::C_S1, other.size());
    h5.createAttribute("format", type, H5::DataSpace(H5S_SCALAR)).write(type, other);
  });
  expect_read_error(file, "not an sphfem model (format 'sphfem-other', expected 'sphfem-model')");
}

TEST_F(ModelFiles, MissingGroupIsNamed) {
  expect_read_error(damaged("no_sets.h5", [](H5::H5File& h5) { h5.unlink("node_sets"); }),
                    "missing group 'node_sets'");
  expect_read_error(damaged("no_elements.h5", [](H5::H5File& h5) { h5.unlink("elements"); }),
                    "missing group 'elements'");
}

// Another program's HDF5 file has no seal; sealed, it still is no model.
TEST_F(ModelFiles, ForeignHdf5FileIsRejected) {
  const fs::path file = path("other.h5");
  H5::H5File(file.string(), H5F_ACC_TRUNC).createGroup("data");
  expect_read_error(file, "other.h5\": an HDF5 file without sphfem's seal");
  H5::H5File(file.string(), H5F_ACC_TRUNC, sealed_file_properties()).createGroup("data");
  seal_h5_file(file);
  expect_read_error(file, "missing attribute 'format'");
}

TEST_F(ModelFiles, TruncatedFileIsAnError) {
  const fs::path whole = path("whole.h5"), cut = path("cut.h5");
  write_model_h5(grid_model(10, 10, 10), whole);
  std::ifstream in(whole, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(cut, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  expect_read_error(cut, "cut.h5\": truncated: " + std::to_string(bytes.size() / 2) + " of the " +
                             std::to_string(bytes.size()) + " bytes sphfem wrote");
}

// One byte changed anywhere in what HDF5 would read is caught before HDF5 reads it.
TEST_F(ModelFiles, ChangedByteIsAnError) {
  const fs::path file = path("flipped.h5");
  write_model_h5(grid_model(3, 2, 2), file);
  const auto size = static_cast<std::streamoff>(fs::file_size(file));
  for (const std::streamoff at : {std::streamoff{512}, size / 2, size - 1}) {
    std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
    io.seekg(at);
    const char byte = static_cast<char>(io.get() ^ 0x10);
    io.seekp(at);
    io.put(byte);
    io.close();
    expect_read_error(file, "flipped.h5\": its content does not match its seal: corrupt or changed "
                            "after sphfem wrote it");
    io.open(file, std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(at);
    io.put(static_cast<char>(byte ^ 0x10));
  }
  EXPECT_EQ(read_model_h5(file).node_count(), 4 * 3 * 3);
}

TEST_F(ModelFiles, MissingDatasetIsNamed) {
  const fs::path file = damaged("no_hex.h5", [](H5::H5File& h5) { h5.unlink("elements/hex"); });
  expect_read_error(file, "missing dataset 'elements/hex'");
}

TEST_F(ModelFiles, NonHdf5FileIsAnError) {
  const fs::path file = path("model.h5");
  std::ofstream(file) << "name: not a model\n";
  expect_read_error(file, "not an HDF5 file");
}

TEST_F(ModelFiles, MissingFileIsAnError) {
  expect_read_error(path("absent.h5"), "no such file");
}

TEST_F(ModelFiles, OutOfRangeConnectivityIsAnError) {
  const fs::path file = damaged("bad_hex.h5", [](H5::H5File& h5) {
    const H5::DataSet hex = h5.openDataSet("elements/hex");
    std::vector<int> values(static_cast<std::size_t>(hex.getSpace().getSimpleExtentNpoints()));
    hex.read(values.data(), H5::PredType::NATIVE_INT);
    values[5] = 4 * 3 * 3; // one past the last node
    hex.write(values.data(), H5::PredType::NATIVE_INT);
  });
  expect_read_error(file, "elements/hex holds index 36");
}

TEST_F(ModelFiles, WrongShapeIsAnError) {
  const fs::path file = damaged("bad_x.h5", [](H5::H5File& h5) {
    h5.unlink("nodes/x");
    const hsize_t dims[2] = {36, 2};
    const std::vector<double> zeros(72, 0.0);
    h5.createDataSet("nodes/x", H5::PredType::IEEE_F64LE, H5::DataSpace(2, dims))
        .write(zeros.data(), H5::PredType::NATIVE_DOUBLE);
  });
  expect_read_error(file, "'nodes/x' must have 3 columns");
}

TEST_F(ModelFiles, OutOfRangeSetIsAnError) {
  const fs::path file = damaged("bad_set.h5", [](H5::H5File& h5) {
    const H5::DataSet set = h5.openDataSet("node_sets/bar/zmin");
    std::vector<int> values(static_cast<std::size_t>(set.getSpace().getSimpleExtentNpoints()));
    set.read(values.data(), H5::PredType::NATIVE_INT);
    values.back() = -1;
    set.write(values.data(), H5::PredType::NATIVE_INT);
  });
  expect_read_error(file, "node set 'bar/zmin' holds index -1");
}

// A model with particles, damaged through HDF5 by `edit` after writing.
class DamagedParticles : public ModelFiles {
protected:
  fs::path damaged_particles(const std::function<void(H5::H5File&)>& edit) const {
    const fs::path file = path("particles.h5");
    write_model_h5(particle_model(5), file);
    {
      H5::H5File h5(file.string(), H5F_ACC_RDWR);
      edit(h5);
    }
    seal_h5_file(file);
    return file;
  }

  // Replaces one value of a 1-D dataset.
  template <class T>
  static void set_value(H5::H5File& h5, const std::string& dataset, std::size_t index, T value) {
    const H5::DataSet d = h5.openDataSet(dataset);
    const H5::PredType& type =
        std::is_same_v<T, int> ? H5::PredType::NATIVE_INT : H5::PredType::NATIVE_DOUBLE;
    std::vector<T> values(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
    d.read(values.data(), type);
    values.at(index) = value;
    d.write(values.data(), type);
  }

  // Replaces a dataset with `values` of shape `dims`.
  static void replace(H5::H5File& h5, const std::string& dataset, std::vector<hsize_t> dims,
                      const std::vector<double>& values) {
    h5.unlink(dataset);
    h5.createDataSet(dataset, H5::PredType::IEEE_F64LE,
                     H5::DataSpace(static_cast<int>(dims.size()), dims.data()))
        .write(values.data(), H5::PredType::NATIVE_DOUBLE);
  }
};

TEST_F(DamagedParticles, NonPositiveMassIsAnError) {
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { set_value(h5, "particles/mass", 3, -1e-6); }),
      "particles/mass holds -1e-06 at index 3 (expected > 0)");
}

TEST_F(DamagedParticles, ZeroSmoothingLengthIsAnError) {
  expect_read_error(damaged_particles([](H5::H5File& h5) { set_value(h5, "particles/h", 0, 0.0); }),
                    "particles/h holds 0 at index 0");
}

TEST_F(DamagedParticles, NonFiniteDensityIsAnError) {
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      set_value(h5, "particles/density", 4,
                                std::numeric_limits<double>::quiet_NaN());
                    }),
                    "particles/density holds nan at index 4");
}

TEST_F(DamagedParticles, NonFinitePositionIsAnError) {
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      std::vector<double> x(15, 0.0);
                      x[7] = std::numeric_limits<double>::infinity();
                      replace(h5, "particles/x", {5, 3}, x);
                    }),
                    "particles/x holds a non-finite position at index 2");
}

TEST_F(DamagedParticles, OutOfRangeBodyIdIsAnError) {
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { set_value(h5, "particles/body_id", 1, 3); }),
      "particles/body_id holds index 3 outside [0, 3)");
}

TEST_F(DamagedParticles, ParticleOfAnFeBodyIsAnError) {
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { set_value(h5, "particles/body_id", 2, 1); }),
      "particles/body_id holds body 1 ('anvil', spacing 0: not an SPH body) at "
      "index 2");
}

TEST_F(DamagedParticles, WrongShapesAreErrors) {
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      replace(h5, "particles/x", {5, 2}, std::vector<double>(10, 0.0));
                    }),
                    "'particles/x' must have 3 columns");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      replace(h5, "particles/mass", {4}, std::vector<double>(4, 1.0));
                    }),
                    "particles/mass has 4 entries for 5 particles");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      replace(h5, "bodies/spacing", {2}, std::vector<double>(2, 1.0));
                    }),
                    "bodies/spacing has 2 entries for 3 bodies");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      replace(h5, "bodies/spacing", {3}, {0, -1, 1});
                    }),
                    "bodies/spacing holds -1 at index 1 (expected >= 0)");
}

TEST_F(DamagedParticles, OutOfRangeParticleFaceIndexIsAnError) {
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      set_value(h5, "particle_faces/ball/zmin/index", 2, 5);
                    }),
                    "particle_faces/ball/zmin/index holds index 5 outside [0, 5)");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      set_value(h5, "particle_faces/ball/side/index", 0, -1);
                    }),
                    "particle_faces/ball/side/index holds index -1");
}

TEST_F(DamagedParticles, NonPositiveParticleFaceAreaIsAnError) {
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      set_value(h5, "particle_faces/ball/zmin/area", 1, 0.0);
                    }),
                    "particle_faces/ball/zmin/area holds 0 at index 1 (expected > 0)");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      set_value(h5, "particle_faces/ball/side/area", 0,
                                std::numeric_limits<double>::infinity());
                    }),
                    "particle_faces/ball/side/area holds inf at index 0");
}

TEST_F(DamagedParticles, BadParticleFaceNormalIsAnError) {
  const auto set_normal = [](H5::H5File& h5, const Vec3& n) {
    const H5::Group face = h5.openGroup("particle_faces/ball/zmin");
    face.openAttribute("normal").write(H5::PredType::NATIVE_DOUBLE, n.data());
  };
  expect_read_error(
      damaged_particles([&](H5::H5File& h5) { set_normal(h5, Vec3(0, 0, -1.001)); }),
      "attribute 'normal' of particle_faces/ball/zmin is not a unit vector: (0, 0, -1.001)");
  expect_read_error(damaged_particles([&](H5::H5File& h5) {
                      set_normal(h5, Vec3(0, std::numeric_limits<double>::quiet_NaN(), 1));
                    }),
                    "is not a unit vector");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      h5.openGroup("particle_faces/ball/zmin").removeAttr("normal");
                    }),
                    "missing attribute 'normal' of particle_faces/ball/zmin");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      const H5::Group face = h5.openGroup("particle_faces/ball/zmin");
                      face.removeAttr("normal");
                      const hsize_t two = 2;
                      const double n[2] = {0, 1};
                      face.createAttribute("normal", H5::PredType::IEEE_F64LE,
                                           H5::DataSpace(1, &two))
                          .write(H5::PredType::NATIVE_DOUBLE, n);
                    }),
                    "attribute 'normal' of particle_faces/ball/zmin is not 3 floating-point "
                    "numbers");
}

TEST_F(DamagedParticles, MalformedParticleFacesAreErrors) {
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      replace(h5, "particle_faces/ball/zmin/area", {2}, {1e-6, 1e-6});
                    }),
                    "particle_faces/ball/zmin/area has 2 entries for 3 particles");
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { h5.unlink("particle_faces/ball/side/area"); }),
      "missing dataset 'particle_faces/ball/side/area'");
  expect_read_error(
      damaged_particles([](H5::H5File& h5) {
        replace(h5, "particle_faces/ball/zmin/index", {3}, {0, 2, 4});
      }),
      "dataset 'particle_faces/ball/zmin/index' has the wrong type (expected integer)");
  // An empty group is a face without its datasets.
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { h5.createGroup("particle_faces/ball/xmax"); }),
      "missing dataset 'particle_faces/ball/xmax/index'");
}

TEST_F(DamagedParticles, MissingParticleDatasetIsNamed) {
  expect_read_error(damaged_particles([](H5::H5File& h5) { h5.unlink("particles/h"); }),
                    "missing dataset 'particles/h'");
}

TEST_F(DamagedParticles, DamagedCouplingIsAnError) {
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      replace(h5, "coupling/h", {2}, {1e-3, 1e-3});
                    }),
                    "coupling/h has 2 entries for 12 background nodes");
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { set_value(h5, "coupling/spacing", 5, -1.0); }),
      "coupling/spacing holds -1 at index 5 (expected > 0)");
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { set_value(h5, "coupling/background_nodes", 11, 99); }),
      "coupling/background_nodes holds index 99 outside [0, 36)");
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { set_value(h5, "coupling/background_nodes", 3, 2); }),
      "coupling/background_nodes is not ascending at index 3 (7 then 2)");
  expect_read_error(damaged_particles([](H5::H5File& h5) { h5.unlink("coupling/h"); }),
                    "missing dataset 'coupling/h'");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      replace(h5, "coupling/background_nodes", {12}, std::vector<double>(12, 1));
                    }),
                    "dataset 'coupling/background_nodes' has the wrong type (expected integer)");
  expect_read_error(
      damaged_particles([](H5::H5File& h5) { set_value(h5, "particles/interface", 1, 2); }),
      "particles/interface holds 2 at index 1 (expected 0 or 1)");
  expect_read_error(damaged_particles([](H5::H5File& h5) {
                      h5.unlink("particles/interface");
                      const hsize_t four = 4;
                      const int flags[4] = {0, 1, 0, 1};
                      h5.createDataSet("particles/interface", H5::PredType::STD_I32LE,
                                       H5::DataSpace(1, &four))
                          .write(flags, H5::PredType::NATIVE_INT);
                    }),
                    "particles/interface has 4 entries for 5 particles");
}

// ---- model.vtu ------------------------------------------------------------------------------

TEST_F(ModelFiles, VtuReadsBackWithHexCellsBodyIdsAndSets) {
  const Model m = grid_model(4, 3, 2);
  const fs::path file = path("model.vtu");
  write_model_vtu(m, file);
  EXPECT_FALSE(fs::exists(path("model.vtu.tmp")));

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfPoints(), m.node_count());
  ASSERT_EQ(grid->GetNumberOfCells(), m.element_count());
  for (Index i = 0; i < m.node_count(); ++i)
    EXPECT_EQ(Vec3(grid->GetPoint(i)), m.x_n[i]);
  vtkNew<vtkIdList> ids;
  for (Index e = 0; e < m.element_count(); ++e) {
    EXPECT_EQ(grid->GetCellType(e), VTK_HEXAHEDRON);
    grid->GetCellPoints(e, ids);
    ASSERT_EQ(ids->GetNumberOfIds(), 8);
    for (int k = 0; k < 8; ++k)
      EXPECT_EQ(ids->GetId(k), m.hex_e[e][k]);
  }
  vtkDataArray* point_body = grid->GetPointData()->GetArray("body_id");
  vtkDataArray* cell_body = grid->GetCellData()->GetArray("body_id");
  ASSERT_NE(point_body, nullptr);
  ASSERT_NE(cell_body, nullptr);
  for (Index i = 0; i < m.node_count(); ++i)
    EXPECT_EQ(point_body->GetTuple1(i), m.body_n[i]);
  for (Index e = 0; e < m.element_count(); ++e)
    EXPECT_EQ(cell_body->GetTuple1(e), m.body_e[e]);
  vtkDataArray* background = grid->GetPointData()->GetArray("background");
  ASSERT_NE(background, nullptr);
  EXPECT_EQ(background->GetDataType(), VTK_INT);
  for (Index i = 0; i < m.node_count(); ++i)
    EXPECT_EQ(background->GetTuple1(i), i % 3 == 1 ? 1 : 0) << "node " << i; // as grid_model
  for (const auto& [name, nodes] : m.node_sets) {
    vtkDataArray* flag = grid->GetPointData()->GetArray(("set:" + name).c_str());
    ASSERT_NE(flag, nullptr) << name;
    double count = 0;
    for (Index i = 0; i < m.node_count(); ++i)
      count += flag->GetTuple1(i);
    EXPECT_EQ(count, static_cast<double>(nodes.size())) << name;
    for (const Index i : nodes)
      EXPECT_EQ(flag->GetTuple1(i), 1) << name;
  }
}

TEST_F(ModelFiles, ParticleVtuReadsBackWithVertexCellsAndArrays) {
  const Model m = particle_model(50);
  const fs::path file = path("model_particles.vtu");
  write_particles_vtu(m, file);
  EXPECT_FALSE(fs::exists(path("model_particles.vtu.tmp")));

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfPoints(), m.particle_count());
  ASSERT_EQ(grid->GetNumberOfCells(), m.particle_count());
  vtkNew<vtkIdList> ids;
  for (Index i = 0; i < m.particle_count(); ++i) {
    EXPECT_EQ(Vec3(grid->GetPoint(i)), m.x_p[i]);
    EXPECT_EQ(grid->GetCellType(i), VTK_VERTEX);
    grid->GetCellPoints(i, ids);
    ASSERT_EQ(ids->GetNumberOfIds(), 1);
    EXPECT_EQ(ids->GetId(0), i);
  }
  const std::vector<std::pair<const char*, const std::vector<double>*>> arrays{
      {"mass", &m.m_p}, {"h", &m.h_p}, {"density", &m.rho_p}};
  for (const auto& [name, values] : arrays) {
    vtkDataArray* array = grid->GetPointData()->GetArray(name);
    ASSERT_NE(array, nullptr) << name;
    for (Index i = 0; i < m.particle_count(); ++i)
      EXPECT_EQ(array->GetTuple1(i), (*values)[i]) << name;
  }
  vtkDataArray* body = grid->GetPointData()->GetArray("body_id");
  ASSERT_NE(body, nullptr);
  for (Index i = 0; i < m.particle_count(); ++i)
    EXPECT_EQ(body->GetTuple1(i), m.body_p[i]);
  vtkDataArray* interface = grid->GetPointData()->GetArray("interface");
  ASSERT_NE(interface, nullptr);
  EXPECT_EQ(interface->GetDataType(), VTK_INT);
  for (Index i = 0; i < m.particle_count(); ++i)
    EXPECT_EQ(interface->GetTuple1(i), m.interface_p[i]);
  // One 0/1 array per particle face.
  ASSERT_EQ(m.particle_faces.size(), 2u);
  for (const auto& [name, face] : m.particle_faces) {
    vtkDataArray* flag = grid->GetPointData()->GetArray(("set:" + name).c_str());
    ASSERT_NE(flag, nullptr) << name;
    EXPECT_EQ(flag->GetDataType(), VTK_INT) << name;
    for (Index i = 0; i < m.particle_count(); ++i)
      EXPECT_EQ(flag->GetTuple1(i),
                std::count(face.particles.begin(), face.particles.end(), i) > 0 ? 1 : 0)
          << name << " particle " << i;
  }
}

TEST_F(ModelFiles, NoParticlesMeansNoParticleVtu) {
  const fs::path file = path("model_particles.vtu");
  write_particles_vtu(grid_model(2, 2, 2), file);
  EXPECT_FALSE(fs::exists(file));
  write_particles_vtu(particle_model(3), file); // a stale file from an earlier model …
  ASSERT_TRUE(fs::exists(file));
  write_particles_vtu(grid_model(2, 2, 2), file); // … is removed
  EXPECT_FALSE(fs::exists(file));
}

TEST_F(ModelFiles, ParticleVtuErrorsNameTheFile) {
  Model m = particle_model(3);
  m.m_p.pop_back();
  const fs::path file = path("model_particles.vtu");
  try {
    write_particles_vtu(m, file);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  const fs::path unwritable = path("no_such_dir") / "model_particles.vtu";
  EXPECT_THROW(write_particles_vtu(particle_model(3), unwritable), Error);
  m = particle_model(3);
  m.particle_faces.at("ball/zmin").particles.push_back(3);
  try {
    write_particles_vtu(m, file);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("particle face 'ball/zmin' holds index 3 outside [0, 3)"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(ModelFiles, VtuUnwritablePathIsAnError) {
  const fs::path file = path("no_such_dir") / "model.vtu";
  try {
    write_model_vtu(grid_model(1, 1, 1), file);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace sphfem
