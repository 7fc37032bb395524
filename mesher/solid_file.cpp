// The volumes of a user's geometry file as closed triangulated surfaces, for filling with SPH
// particles (lattice.cpp, ray_parity.cpp). gmsh reads the file (merge, not open: in gmsh 4.8 a
// syntax error in a .geo leaves open() refusing every later file for the rest of the session;
// mesh_case also gives each file a fresh session, so options its script sets do not leak) and
// meshes only the surfaces: a point is inside a volume when its boundary's triangulation
// encloses it. (gmsh 4.8's model::isInside does not handle volumes, and a tetrahedral mesh
// would have the same boundary at a far higher cost.) The surface mesher is Delaunay, the fastest
// here; gmsh falls back to MeshAdapt on surfaces Delaunay cannot do. Coordinates are taken as
// metres: a STEP file in millimetres needs a .geo wrapper that merges it with
// Geometry.OCCScaling = 0.001. Verified by tests/mesher/lattice_test.cpp.
#include "mesher/lattice.hpp"

#include "solver/core/error.hpp"

#include <gmsh.h>

#include <algorithm>
#include <limits>
#include <map>

namespace sphfem::mesher {
namespace {

constexpr int gmsh_triangle = 2;
constexpr int gmsh_quad = 3;

// gmsh node tag → position, for every node of the current model.
class NodePositions {
public:
  NodePositions() {
    std::vector<double> coord, parametric;
    gmsh::model::mesh::getNodes(tags_, coord, parametric, -1, -1, false, false);
    const std::size_t max_tag = tags_.empty() ? 0 : *std::max_element(tags_.begin(), tags_.end());
    position_.assign(max_tag + 1, Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
    for (std::size_t i = 0; i < tags_.size(); ++i)
      position_[tags_[i]] = Vec3(coord[3 * i], coord[3 * i + 1], coord[3 * i + 2]);
  }
  const Vec3& operator()(std::size_t tag) const {
    SPHFEM_CHECK(tag < position_.size() && position_[tag].allFinite(), "unknown gmsh node ", tag);
    return position_[tag];
  }

private:
  std::vector<std::size_t> tags_;
  std::vector<Vec3> position_;
};

// Builds one volume's triangulation, numbering its vertices in order of first use.
class SurfaceBuilder {
public:
  explicit SurfaceBuilder(const NodePositions& nodes) : nodes_(nodes) {}

  void add(std::size_t a, std::size_t b, std::size_t c) {
    if (a == b || b == c || c == a)
      return; // collapsed (gmsh can leave these at degenerate points such as a sphere's poles)
    surface_.triangles.push_back({vertex(a), vertex(b), vertex(c)});
  }

  // Triangles and quads (split along a diagonal) of one boundary surface.
  void add_surface(int surface) {
    std::vector<int> types;
    gmsh::model::mesh::getElementTypes(types, 2, surface);
    SPHFEM_CHECK(!types.empty(), "surface ", surface, " could not be meshed");
    for (const int type : types) {
      SPHFEM_CHECK(type == gmsh_triangle || type == gmsh_quad, "surface ", surface,
                   " is meshed with gmsh element type ", type, ", not triangles or quadrangles");
      std::vector<std::size_t> elements, n;
      gmsh::model::mesh::getElementsByType(type, elements, n, surface);
      if (type == gmsh_triangle)
        for (std::size_t e = 0; e < n.size(); e += 3)
          add(n[e], n[e + 1], n[e + 2]);
      else
        for (std::size_t e = 0; e < n.size(); e += 4) {
          add(n[e], n[e + 1], n[e + 2]);
          add(n[e], n[e + 2], n[e + 3]);
        }
    }
  }

  // The triangulation, after checking it is closed: every edge is used an even number of times.
  Triangulation finish(int volume) {
    std::map<std::pair<Index, Index>, int> uses;
    for (const auto& t : surface_.triangles)
      for (int e = 0; e < 3; ++e)
        ++uses[std::minmax(t[e], t[(e + 1) % 3])];
    for (const auto& [edge, count] : uses)
      SPHFEM_CHECK(count % 2 == 0, "the boundary of volume ", volume,
                   " is not closed (a surface mesh edge at ", surface_.x[edge.first].transpose(),
                   " is used by ", count, " triangle", count == 1 ? "" : "s", ")");
    SPHFEM_CHECK(!surface_.triangles.empty(), "volume ", volume, " has an empty boundary");
    return std::move(surface_);
  }

private:
  Index vertex(std::size_t tag) {
    const auto [at, added] = index_.try_emplace(tag, static_cast<Index>(surface_.x.size()));
    if (added)
      surface_.x.push_back(nodes_(tag));
    return at->second;
  }

  const NodePositions& nodes_;
  std::map<std::size_t, Index> index_;
  Triangulation surface_;
};

} // namespace

std::vector<Triangulation> solid_boundaries(const std::filesystem::path& file, double size) {
  gmsh::clear();
  gmsh::merge(file.string());
  gmsh::vectorpair volumes;
  gmsh::model::getEntities(volumes, 3);
  SPHFEM_CHECK(!volumes.empty(), "geometry file ", file.string(),
               " defines no volume (a closed solid is needed)");
  gmsh::option::setNumber("Mesh.MeshSizeMax", size);
  gmsh::option::setNumber("Mesh.Algorithm", 5); // Delaunay
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  gmsh::model::mesh::generate(2);
  const NodePositions nodes;
  std::vector<Triangulation> out;
  for (const auto& volume : volumes) {
    gmsh::vectorpair surfaces;
    gmsh::model::getBoundary({volume}, surfaces, false, false, false);
    SurfaceBuilder builder(nodes);
    for (const auto& [dim, surface] : surfaces)
      builder.add_surface(surface);
    out.push_back(builder.finish(volume.second));
  }
  return out;
}

} // namespace sphfem::mesher
