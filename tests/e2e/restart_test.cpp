// Nothing lost (issue 9): a solve killed with SIGKILL at a random step, or stopped with SIGINT,
// leaves every file readable and continues from its checkpoint to the very files an
// uninterrupted run writes — history.csv, history.h5, results.pvd, every frame and summary.json
// but its wall times — at the same thread count. A restart whose physics keys differ is
// refused before anything is written. The reference is the uninterrupted run itself: the
// restart must reproduce it bit for bit, not approximately.
#include "post/post.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/io/sealed_h5.hpp"
#include "tests/support/command.hpp"

#include <H5Cpp.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <random>
#include <string>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using sphfem::test::slurp;

namespace {

const std::string case_file = std::string(SPHFEM_SOURCE_DIR) + "/cases/bar_impact/case.yaml";
// bar_impact 5× longer than shipped (about 2 000 steps), a checkpoint every 100 steps.
const std::string keys = " --set time.end=1e-3 --set time.output_interval=1e-4"
                         " --set output.checkpoint.steps=100 -j 2 -q";

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("sphfem_restart_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

int run(const std::string& args, const fs::path& dir) {
  int status = 0;
  ::waitpid(sphfem::test::spawn_sphfem(args, dir), &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

nlohmann::json summary_without_wall_time(const fs::path& out) {
  nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  s.erase("wall_s");
  s.erase("entity_steps_per_s");
  s.erase("peak_resident_MB");
  return s;
}

// The files of `out` equal those of the uninterrupted run, byte for byte.
void expect_same_as_uninterrupted(const fs::path& out, const fs::path& reference) {
  // Compared as whole files; EXPECT_TRUE, not EXPECT_EQ: a failure names the file instead of
  // printing its bytes.
  for (const char* file : {"history.csv", "history.h5", "results.pvd"})
    EXPECT_TRUE(slurp(out / file) == slurp(reference / file)) << file << " differs";
  EXPECT_EQ(summary_without_wall_time(out), summary_without_wall_time(reference));
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(reference / "frames")) {
    const fs::path name = entry.path().filename();
    EXPECT_TRUE(slurp(out / "frames" / name) == slurp(entry.path())) << name << " differs";
    ++frames;
  }
  EXPECT_EQ(frames, 22); // frames at 0, 0.1, …, 1 ms for the FE bar and the particle bar
}

class Restart : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    reference_ = new fs::path(scratch("reference"));
    ASSERT_EQ(run("solve " + case_file + " -o " + reference_->string() + keys, *reference_), 0)
        << slurp(*reference_ / "stderr.txt");
  }
  static void TearDownTestSuite() {
    if (!HasFailure())
      fs::remove_all(*reference_);
    delete reference_;
  }
  // Continues the run in `out` from its checkpoint and compares its files with the reference's.
  static void resume_and_compare(const fs::path& dir, const fs::path& out) {
    ASSERT_EQ(run("solve " + case_file + " -o " + out.string() + keys + " --restart " +
                      (out / "checkpoint.h5").string(),
                  dir),
              0)
        << slurp(dir / "stderr.txt");
    expect_same_as_uninterrupted(out, *reference_);
    for (const auto& entry : fs::recursive_directory_iterator(out))
      EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
    if (!HasFailure())
      fs::remove_all(dir);
  }

  static fs::path* reference_;
};

fs::path* Restart::reference_ = nullptr;

} // namespace

TEST_F(Restart, KilledAtARandomStepContinuesToTheSameFiles) {
  const fs::path dir = scratch("killed"), out = dir / "out";
  const pid_t pid =
      sphfem::test::spawn_sphfem("solve " + case_file + " -o " + out.string() + keys, dir);
  ASSERT_TRUE(sphfem::test::wait_for_file(out / "checkpoint.h5", pid)) << slurp(dir / "stderr.txt");
  std::mt19937 random(std::random_device{}());
  std::this_thread::sleep_for(
      std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 1500)(random)));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it could be killed";

  // Every file readable as it was left.
  const auto meta = sphfem::read_checkpoint_meta(out / "checkpoint.h5");
  EXPECT_GT(meta.steps, 0);
  EXPECT_EQ(meta.steps % 100, 0);
  EXPECT_GT(sphfem::post::read_history_csv(out / "history.csv").rows(), 0u);
  for (const auto& [time, frame] : sphfem::post::read_pvd(out / "results.pvd"))
    EXPECT_TRUE(fs::exists(out / frame)) << frame;
  // A write the kill cut short leaves its temporary (nothing can remove it after SIGKILL) and
  // the file it was to replace whole (a new frame's has none, and the .pvd does not list it);
  // the restart writes each again.
  for (const auto& entry : fs::directory_iterator(out))
    if (entry.path().extension() == ".tmp") {
      EXPECT_TRUE(fs::exists(fs::path(entry.path()).replace_extension())) << entry.path();
    }

  resume_and_compare(dir, out);
}

TEST_F(Restart, SigintCheckpointsSaysHowToContinueAndResumes) {
  const fs::path dir = scratch("sigint"), out = dir / "out";
  const pid_t pid =
      sphfem::test::spawn_sphfem("solve " + case_file + " -o " + out.string() + keys, dir);
  ASSERT_TRUE(sphfem::test::wait_for_file(out / "checkpoint.h5", pid)) << slurp(dir / "stderr.txt");
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
  const std::string message = slurp(dir / "stderr.txt");
  EXPECT_NE(message.find("interrupted by SIGINT at t = "), std::string::npos) << message;
  EXPECT_NE(message.find("--restart " + (out / "checkpoint.h5").string()), std::string::npos)
      << message;
  // A checkpoint of a step before the end (the one the signal interrupted; that it is not the
  // last periodic one cannot be asserted: the signal may land on a multiple of 100).
  const auto meta = sphfem::read_checkpoint_meta(out / "checkpoint.h5");
  EXPECT_GT(meta.steps, 0);
  EXPECT_LT(meta.time, 1e-3);

  resume_and_compare(dir, out);
}

TEST_F(Restart, OtherPhysicsIsRefusedAndNothingIsTouched) {
  const fs::path dir = scratch("refused"), out = dir / "out";
  fs::copy(*reference_, out, fs::copy_options::recursive);
  const std::string before = slurp(out / "checkpoint.h5"), model = slurp(out / "model.h5");
  const std::string restart = " --restart " + (out / "checkpoint.h5").string();
  EXPECT_EQ(run("solve " + case_file + " -o " + out.string() + keys +
                    " --set bodies.bar_a.velocity=[0,0,150]" + restart,
                dir),
            1);
  const std::string message = slurp(dir / "stderr.txt");
  EXPECT_NE(message.find("the case's physics differs from the checkpoint's"), std::string::npos)
      << message;
  EXPECT_NE(message.find("bodies.bar_a.velocity.2: checkpoint 200, case 150"), std::string::npos)
      << message;
  // A different spacing would re-mesh: refused before model.h5 is replaced.
  EXPECT_EQ(run("solve " + case_file + " -o " + out.string() + keys +
                    " --set bodies.bar_b.element_size=0.005" + restart,
                dir),
            1);
  EXPECT_TRUE(slurp(out / "checkpoint.h5") == before) << "the checkpoint was touched";
  EXPECT_TRUE(slurp(out / "model.h5") == model) << "model.h5 was touched";
  // A checkpoint whose meta reads but a field does not: refused, and the history as it was.
  const fs::path damaged = dir / "damaged.h5";
  fs::copy_file(out / "checkpoint.h5", damaged);
  H5::H5File(damaged.string(), H5F_ACC_RDWR).unlink("particles/x_p");
  sphfem::seal_h5_file(damaged);
  const std::string history = slurp(out / "history.csv");
  EXPECT_EQ(
      run("solve " + case_file + " -o " + out.string() + keys + " --restart " + damaged.string(),
          dir),
      1);
  EXPECT_NE(slurp(dir / "stderr.txt").find("field particles/x_p is missing"), std::string::npos)
      << slurp(dir / "stderr.txt");
  EXPECT_TRUE(slurp(out / "history.csv") == history) << "history.csv was touched";
  // The same physics keys, but the checkpoint's model is not the one in OUT (as when model.h5 is
  // replaced by hand): refused, naming both fingerprints.
  const fs::path other_model = dir / "other_model.h5";
  fs::copy_file(out / "checkpoint.h5", other_model);
  {
    H5::H5File h5(other_model.string(), H5F_ACC_RDWR);
    h5.unlink("meta/model");
    const std::string text = "another model";
    const std::array<hsize_t, 2> dims{text.size(), 1}; // a text field: bytes, one per element
    const H5::DataSet field =
        h5.createDataSet("meta/model", H5::PredType::NATIVE_UCHAR, H5::DataSpace(2, dims.data()));
    field.write(text.data(), H5::PredType::NATIVE_UCHAR);
    const int one = 1;
    field.createAttribute("element_bytes", H5::PredType::STD_I32LE, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_INT, &one);
  }
  sphfem::seal_h5_file(other_model);
  EXPECT_EQ(run("solve " + case_file + " -o " + out.string() + keys + " --restart " +
                    other_model.string(),
                dir),
            1);
  EXPECT_NE(slurp(dir / "stderr.txt")
                .find("was made from another model (another model; this case "
                      "meshes to "),
            std::string::npos)
      << slurp(dir / "stderr.txt");
  EXPECT_TRUE(slurp(out / "history.csv") == history) << "history.csv was touched";
  // Output-only keys may change: a longer end time continues from the end checkpoint.
  EXPECT_EQ(run("solve " + case_file + " -o " + out.string() + keys +
                    " --set time.end=1.1e-3 --set output.frames=false" + restart,
                dir),
            0)
      << slurp(dir / "stderr.txt");
  EXPECT_NEAR(nlohmann::json::parse(slurp(out / "summary.json"))["time"].get<double>(), 1.1e-3,
              1e-12);
  if (!HasFailure())
    fs::remove_all(dir);
}
