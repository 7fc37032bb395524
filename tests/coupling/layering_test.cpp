// The seam between the phases (issue 28, point 0): the particle phase (solver/sph) and the
// element phase (solver/fem) include nothing of each other, of their coupling (solver/coupling)
// or of the step that composes them (solver/time), so that each can be built, decomposed and
// tested on its own. Read from the sources' #include lines.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// "file:line: include" for each #include of one of `forbidden` in the sources of `folder`.
std::vector<std::string> includes_of(const std::string& folder,
                                     const std::vector<std::string>& forbidden) {
  std::vector<std::string> found;
  const fs::path root = fs::path(SPHFEM_SOURCE_DIR) / "solver" / folder;
  for (const auto& entry : fs::directory_iterator(root)) {
    const auto ext = entry.path().extension();
    if (ext != ".hpp" && ext != ".cpp")
      continue;
    std::ifstream in(entry.path());
    std::string line;
    for (int number = 1; std::getline(in, line); ++number)
      for (const auto& other : forbidden)
        if (line.rfind("#include \"solver/" + other + "/", 0) == 0)
          found.push_back(entry.path().filename().string() + ":" + std::to_string(number) + ": " +
                          line);
  }
  return found;
}

} // namespace

TEST(Layering, ParticlePhaseKnowsNothingOfElementsCouplingOrStep) {
  const auto found = includes_of("sph", {"fem", "coupling", "time"});
  EXPECT_TRUE(found.empty()) << found.front();
}

TEST(Layering, ElementPhaseKnowsNothingOfParticlesCouplingOrStep) {
  const auto found = includes_of("fem", {"sph", "coupling", "time"});
  EXPECT_TRUE(found.empty()) << found.front();
}

TEST(Layering, TheCheckSeesIncludes) {
  // The step composes all three: if the scan found nothing there, it would prove nothing above.
  EXPECT_FALSE(includes_of("time", {"sph"}).empty());
  EXPECT_FALSE(includes_of("time", {"coupling"}).empty());
}
