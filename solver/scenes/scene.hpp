// The scenes library: a scene (`scene: <name>` in a case file, DESIGN.md "Case file") states a
// few physical parameters and expands them into ordinary bodies, couplings, conditions and a
// section, so that a user describes an experiment rather than its model. One file per scene
// (plate_impact.cpp, …); this registry is the one list the case reader consults, so a new scene
// is a new file and a line in scene.cpp, not a branch in the reader. Verified by
// tests/scenes/scene_test.cpp and each scene's own test.
#pragma once

#include "solver/io/case.hpp"
#include "solver/io/case_node.hpp"

#include <string_view>
#include <vector>

namespace sphfem {

struct SceneType {
  std::string_view name;
  // The top-level keys the scene reads beside those every case has (name, scene, time,
  // materials, probes, fem, sph, output).
  std::vector<std::string_view> keys;
  // Reads the scene's blocks from the case's top level and appends its bodies, couplings,
  // conditions, section and SceneSpec to `c`, whose materials and options are already read.
  void (*read)(const CaseNode& root, Case& c);
};

// Every scene, in the order --help lists them.
const std::vector<SceneType>& scene_types();

} // namespace sphfem
