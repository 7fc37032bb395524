// checkpoint.h5 (solver/io/checkpoint.hpp): what persist() stores comes back exactly — numbers,
// vectors and matrices, structs with padding, text, empty arrays — and every kind of bad file
// (absent, not HDF5, unsealed, truncated, changed, another format or version, a field missing
// or of another layout, a history or frame list of another run or damaged) is a one-line Error
// naming the file, never a crash. The model fingerprint changes with
// the model's content and not with anything else.
#include "solver/core/error.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/io/frame_writer.hpp"
#include "solver/io/history_writer.hpp"
#include "solver/io/sealed_h5.hpp"
#include "solver/material/material_point.hpp"

#include <gtest/gtest.h>

#include <H5Cpp.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
using namespace sphfem;

namespace {

struct Folder {
  fs::path dir = fs::temp_directory_path() / ("sphfem_checkpoint_" + std::to_string(::getpid()));
  Folder() { fs::create_directories(dir); }
  ~Folder() { fs::remove_all(dir); }
};

// A little of everything a run persists.
struct State {
  double time = 0;
  long long steps = 0;
  std::vector<Vec3> x;
  std::vector<Mat3> S;
  std::vector<MaterialPoint> point;
  std::vector<int> empty;
  std::string frames;

  void persist(StateArchive& a) {
    a.value("simulation/time", time);
    a.value("simulation/steps", steps);
    a.array("particles/x_p", x);
    a.array("particles/S_p", S);
    a.array("elements/point_e", point);
    a.array("particles/empty", empty);
    a.text("run/frames", frames);
  }
};

State sample() {
  State s;
  s.time = 1.0 / 3.0;
  s.steps = 123456789012LL;
  s.x = {Vec3(1e-300, -0.0, 5.0), Vec3(std::nextafter(1.0, 2.0), 2, 3)};
  s.S = {Mat3::Random(), Mat3::Random()};
  MaterialPoint p;
  p.plastic_strain = 0.25, p.damage = 0.5, p.temperature = 400, p.failed = true;
  s.point = {p, MaterialPoint{}};
  s.frames = "0 0 frames/fe_000000.vtu\n1e-05 1 frames/sph_000001.vtu\n";
  return s;
}

CheckpointMeta meta() {
  return {
      2.5e-5, 77, 2, "model fingerprint", {{"time.cfl", "0.5"}, {"bodies.bar.spacing", "1e-3"}}};
}

// The message of the Error that reading `file` with `read` throws; empty if none is thrown.
std::string read_error(const fs::path& file, const std::function<void(StateArchive&)>& read) {
  try {
    read_checkpoint(file, read);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string error_of(const fs::path& file) {
  State s;
  return read_error(file, [&](StateArchive& a) { s.persist(a); });
}

Model small_model() {
  Model m;
  m.body_names = {"plate"};
  m.x_n = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  m.body_n = {0, 0};
  m.x_p = {Vec3(0.5, 0.5, 0.5)};
  m.m_p = {1.0};
  return m;
}

} // namespace

TEST(Checkpoint, FieldsComeBackBitForBit) {
  const Folder f;
  const fs::path file = f.dir / "checkpoint.h5";
  State written = sample();
  write_checkpoint(file, meta(), [&](StateArchive& a) { written.persist(a); });
  EXPECT_FALSE(fs::exists(f.dir / "checkpoint.h5.tmp"));

  const CheckpointMeta m = read_checkpoint_meta(file);
  EXPECT_EQ(m.time, 2.5e-5);
  EXPECT_EQ(m.steps, 77);
  EXPECT_EQ(m.threads, 2);
  EXPECT_EQ(m.model, "model fingerprint");
  EXPECT_EQ(m.case_keys, meta().case_keys);

  State read;
  read.empty = {1, 2, 3}; // replaced by the stored (empty) array
  read_checkpoint(file, [&](StateArchive& a) { read.persist(a); });
  EXPECT_EQ(read.time, written.time);
  EXPECT_EQ(read.steps, written.steps);
  ASSERT_EQ(read.x.size(), 2u);
  EXPECT_EQ(read.x[0], written.x[0]);
  EXPECT_EQ(read.x[1], written.x[1]);
  EXPECT_TRUE(std::signbit(read.x[0].y())); // −0 stays −0: bytes, not decimal text
  EXPECT_EQ(read.S[1], written.S[1]);
  EXPECT_EQ(read.point[0].plastic_strain, 0.25);
  EXPECT_EQ(read.point[0].temperature, 400);
  EXPECT_TRUE(read.point[0].failed);
  EXPECT_FALSE(read.point[1].failed);
  EXPECT_TRUE(read.empty.empty());
  EXPECT_EQ(read.frames, written.frames);
}

TEST(Checkpoint, ANewCheckpointReplacesTheOldOnlyWhenComplete) {
  const Folder f;
  const fs::path file = f.dir / "checkpoint.h5";
  State first = sample();
  write_checkpoint(file, meta(), [&](StateArchive& a) { first.persist(a); });
  // A write that fails half-way (here: a field an archive cannot hold twice) leaves the
  // previous checkpoint in place and readable.
  EXPECT_THROW(write_checkpoint(file, meta(),
                                [&](StateArchive& a) {
                                  first.persist(a);
                                  first.persist(a);
                                }),
               Error);
  EXPECT_EQ(read_checkpoint_meta(file).steps, 77);
  EXPECT_EQ(error_of(file), "");
  EXPECT_FALSE(fs::exists(f.dir / "checkpoint.h5.tmp"));
}

TEST(Checkpoint, BadFilesAreOneLineErrors) {
  const Folder f;
  const fs::path good = f.dir / "checkpoint.h5";
  State s = sample();
  write_checkpoint(good, meta(), [&](StateArchive& a) { s.persist(a); });

  const fs::path text = f.dir / "text.h5";
  std::ofstream(text) << "not a checkpoint\n";
  const fs::path truncated = f.dir / "truncated.h5";
  {
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const fs::path changed = f.dir / "changed.h5"; // one byte of the content changed
  fs::copy_file(good, changed);
  {
    std::fstream io(changed, std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(static_cast<std::streamoff>(fs::file_size(good) / 2));
    io.put('\x5a');
  }
  const fs::path unsealed = f.dir / "unsealed.h5"; // another program's HDF5 file
  H5::H5File(unsealed.string(), H5F_ACC_TRUNC).close();
  // Below, files damaged through HDF5 and sealed again: the reader's checks behind the seal.
  const fs::path other = f.dir / "other.h5"; // an HDF5 file of another kind
  H5::H5File(other.string(), H5F_ACC_TRUNC, sealed_file_properties()).close();
  seal_h5_file(other);
  const fs::path number_format = f.dir / "number_format.h5"; // format an integer, not a string
  fs::copy_file(good, number_format);
  {
    H5::H5File h5(number_format.string(), H5F_ACC_RDWR);
    h5.removeAttr("format");
    const int one = 1;
    h5.createAttribute("format", H5::PredType::STD_I32LE, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_INT, &one);
  }
  seal_h5_file(number_format);
  const fs::path other_format = f.dir / "other_format.h5"; // a string, but another format's
  fs::copy_file(good, other_format);
  {
    H5::H5File h5(other_format.string(), H5F_ACC_RDWR);
    h5.removeAttr("format");
    const std::string name = "sphfem-model";
    const H5::StrType type(H5::PredType::C_S1, name.size());
    h5.createAttribute("format", type, H5::DataSpace(H5S_SCALAR)).write(type, name);
  }
  seal_h5_file(other_format);
  const fs::path version = f.dir / "version.h5";
  fs::copy_file(good, version);
  {
    H5::H5File h5(version.string(), H5F_ACC_RDWR);
    const int three = 3;
    h5.openAttribute("version").write(H5::PredType::NATIVE_INT, &three);
  }
  seal_h5_file(version);

  EXPECT_NE(error_of(f.dir / "absent.h5").find("absent.h5\": no such file"), std::string::npos);
  EXPECT_NE(error_of(f.dir).find("not a regular file"), std::string::npos);
  EXPECT_NE(error_of(text).find("text.h5\": not an HDF5 file"), std::string::npos);
  EXPECT_NE(error_of(truncated).find("truncated.h5\": "), std::string::npos);
  EXPECT_NE(error_of(other).find("other.h5\": not a checkpoint (no format attribute)"),
            std::string::npos);
  EXPECT_NE(error_of(number_format)
                .find("number_format.h5\": not a checkpoint (its format attribute is not a short "
                      "string)"),
            std::string::npos);
  EXPECT_NE(
      error_of(other_format).find("other_format.h5\": not a checkpoint (format \"sphfem-model\")"),
      std::string::npos)
      << error_of(other_format);
  EXPECT_NE(error_of(version).find("checkpoint version 3, this sphfem reads 2"), std::string::npos);
  EXPECT_NE(error_of(truncated).find(
                "truncated.h5\": truncated: " + std::to_string(fs::file_size(truncated)) +
                " of the " + std::to_string(fs::file_size(good)) + " bytes sphfem wrote"),
            std::string::npos)
      << error_of(truncated);
  EXPECT_NE(error_of(changed).find("changed.h5\": its content does not match its seal"),
            std::string::npos)
      << error_of(changed);
  EXPECT_NE(error_of(unsealed).find("unsealed.h5\": an HDF5 file without sphfem's seal"),
            std::string::npos)
      << error_of(unsealed);

  // A field that is absent, or stored with another element size (another build's layout).
  try {
    read_checkpoint(good, [](StateArchive& a) {
      std::vector<double> v;
      a.array("particles/rho_p", v);
    });
    ADD_FAILURE() << "a missing field was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("field particles/rho_p is missing"), std::string::npos)
        << e.what();
  }
  try {
    read_checkpoint(good, [](StateArchive& a) {
      std::vector<float> v; // stored as Vec3 (24 bytes)
      a.array("particles/x_p", v);
    });
    ADD_FAILURE() << "a field of another layout was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("elements of 24 bytes, this build's are 4"),
              std::string::npos)
        << e.what();
  }
}

// A file that is a checkpoint but whose content disagrees with what reading expects.
TEST(Checkpoint, InconsistentContentIsAnError) {
  const Folder f;
  const fs::path file = f.dir / "checkpoint.h5";
  State s = sample();
  write_checkpoint(file, meta(), [&](StateArchive& a) { s.persist(a); });
  const auto error = [&](const auto& read) { return read_error(file, read); };
  // A value where an array of two is stored.
  EXPECT_NE(error([](StateArchive& a) {
              Vec3 x;
              a.value("particles/x_p", x);
            }).find("field particles/x_p: 2 values stored, 1 expected"),
            std::string::npos);
  {
    H5::H5File h5(file.string(), H5F_ACC_RDWR);
    const hsize_t three = 3; // a dataset of rank 1 where a field is expected
    h5.createDataSet("particles/flat", H5::PredType::NATIVE_UCHAR, H5::DataSpace(1, &three));
    const std::array<hsize_t, 2> dims{1000000, 8}; // claims 8 MB, stores nothing
    const H5::DataSet claim = h5.createDataSet("particles/claim", H5::PredType::NATIVE_UCHAR,
                                               H5::DataSpace(2, dims.data()));
    const int eight = 8;
    claim.createAttribute("element_bytes", H5::PredType::STD_I32LE, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_INT, &eight);
    const std::array<hsize_t, 2> one{1, 8};
    h5.createDataSet("particles/bare", H5::PredType::NATIVE_UCHAR, H5::DataSpace(2, one.data()));
  }
  seal_h5_file(file);
  const auto read_doubles = [&](const std::string& name) {
    return error([&](StateArchive& a) {
      std::vector<double> v;
      a.array(name, v);
    });
  };
  EXPECT_NE(read_doubles("particles/flat").find("field particles/flat: not a field"),
            std::string::npos);
  EXPECT_NE(read_doubles("particles/claim")
                .find("field particles/claim claims more data than the file holds"),
            std::string::npos);
  EXPECT_NE(read_doubles("particles/bare").find("field particles/bare: no element size"),
            std::string::npos);
  // Case keys that are not the JSON object a checkpoint writes.
  {
    H5::H5File h5(file.string(), H5F_ACC_RDWR);
    h5.unlink("meta/case_keys");
  }
  {
    std::string broken = "{not json";
    H5::H5File h5(file.string(), H5F_ACC_RDWR);
    const std::array<hsize_t, 2> dims{broken.size(), 1};
    const H5::DataSet keys = h5.createDataSet("meta/case_keys", H5::PredType::NATIVE_UCHAR,
                                              H5::DataSpace(2, dims.data()));
    keys.write(broken.data(), H5::PredType::NATIVE_UCHAR);
    const int one_byte = 1;
    keys.createAttribute("element_bytes", H5::PredType::STD_I32LE, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_INT, &one_byte);
  }
  seal_h5_file(file);
  try {
    read_checkpoint_meta(file);
    ADD_FAILURE() << "broken case keys were read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unreadable case keys"), std::string::npos) << e.what();
  }
}

// The history and frame writers' parts of a checkpoint, read back by writers of another run or
// stored inconsistently (by hand or by damage): refused with what is wrong.
TEST(Checkpoint, RunOutputsOfAnotherKindAreRefused) {
  const Folder f;
  const fs::path file = f.dir / "checkpoint.h5";
  const auto refusal = [&](const auto& read) { return read_error(file, read); };

  HistoryWriter written(f.dir / "written", {"time", "energy"});
  written.append({0.0, 1.0});
  write_checkpoint(file, meta(), [&](StateArchive& a) { written.persist(a); });
  HistoryWriter other_columns(f.dir / "other", {"time", "momentum"});
  EXPECT_NE(refusal([&](StateArchive& a) {
              other_columns.persist(a);
            }).find("its history has other columns than this run's"),
            std::string::npos);

  write_checkpoint(file, meta(), [](StateArchive& a) {
    std::string columns = "time\nenergy\n";
    std::vector<double> rows{0.0, 1.0, 2.0}; // a row and a half
    a.text("run/history_columns", columns);
    a.array("run/history_rows", rows);
  });
  HistoryWriter same_columns(f.dir / "same", {"time", "energy"});
  EXPECT_NE(refusal([&](StateArchive& a) {
              same_columns.persist(a);
            }).find("history rows of 3 values for 2 columns"),
            std::string::npos);

  write_checkpoint(file, meta(), [](StateArchive& a) {
    std::string frames = "0 0 frames/fe_000000.vtu\nlater 1 frames/sph_000001.vtu\n";
    int count = 2;
    a.text("run/frames", frames);
    a.value("run/frame_count", count);
  });
  const Nodes nodes;
  const HexElements elements;
  const Particles particles;
  FrameWriter frames(f.dir / "frames", elements, particles, {});
  EXPECT_NE(refusal([&](StateArchive& a) { frames.persist(a); }).find("unreadable frame list"),
            std::string::npos);
}

TEST(Checkpoint, ModelFingerprintFollowsTheContent) {
  const Model a = small_model();
  Model moved = a, renamed = a;
  moved.x_n[1].x() = std::nextafter(1.0, 2.0);
  renamed.body_names = {"plat"};
  EXPECT_EQ(model_fingerprint(a), model_fingerprint(small_model()));
  EXPECT_NE(model_fingerprint(a), model_fingerprint(moved));
  EXPECT_NE(model_fingerprint(a), model_fingerprint(renamed));
  EXPECT_NE(model_fingerprint(a).find("2 nodes, 0 hexahedra, 1 particles"), std::string::npos);
}
