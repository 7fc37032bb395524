// The registry of scenes (see the header): one line per scene.
#include "solver/scenes/scene.hpp"

#include "solver/scenes/plate_impact.hpp"

namespace sphfem {

const std::vector<SceneType>& scene_types() {
  static const std::vector<SceneType> types{
      {"plate_impact", {"preset", "symmetry", "plate", "core", "projectile"}, read_plate_impact},
  };
  return types;
}

} // namespace sphfem
