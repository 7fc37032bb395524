// Structured hex mesh of a box: an OCC box with transfinite curves, surfaces and volume,
// recombined into n_x·n_y·n_z hexahedra; faces xmin … zmax. Verified by
// tests/mesher/mesher_test.cpp.
#include "mesher/gmsh_body.hpp"
#include "solver/core/error.hpp"

#include <gmsh.h>

#include <array>

namespace sphfem::mesher {
namespace {

struct Extent {
  Vec3 low, high;
  Vec3 size() const { return high - low; }
  Vec3 centre() const { return 0.5 * (low + high); }
};

// OCC pads bounding boxes by a tolerance, so callers compare extents, not coordinates.
Extent bounding_box(int dim, int tag) {
  Extent e;
  gmsh::model::getBoundingBox(dim, tag, e.low.x(), e.low.y(), e.low.z(), e.high.x(), e.high.y(),
                              e.high.z());
  return e;
}

std::vector<int> entities(int dim) {
  gmsh::vectorpair dim_tags;
  gmsh::model::getEntities(dim_tags, dim);
  std::vector<int> tags;
  for (const auto& [d, tag] : dim_tags)
    tags.push_back(tag);
  return tags;
}

void name_faces(const std::string& body, const Vec3& centre) {
  static constexpr std::array<std::array<const char*, 2>, 3> names{
      {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}}};
  for (const int surface : entities(2)) {
    const Extent e = bounding_box(2, surface);
    Eigen::Index axis = 0;
    e.size().minCoeff(&axis); // a face is flat across its normal
    const bool high = e.centre()[axis] > centre[axis];
    add_named_face(body + "/" + names[axis][high ? 1 : 0], {surface});
  }
}

} // namespace

Placement build_box(const BodySpec& body) {
  const BoxGeometry& box = body.geometry.box;
  const Vec3 size = box.max - box.min;
  SPHFEM_CHECK(size.allFinite() && (size.array() > 0).all(),
               "box max must exceed min in every direction");
  const std::array<int, 3> n{divisions(size.x(), body.element_size),
                             divisions(size.y(), body.element_size),
                             divisions(size.z(), body.element_size)};

  const int volume =
      gmsh::model::occ::addBox(box.min.x(), box.min.y(), box.min.z(), size.x(), size.y(), size.z());
  gmsh::model::occ::synchronize();
  for (const int curve : entities(1)) {
    Eigen::Index axis = 0;
    bounding_box(1, curve).size().maxCoeff(&axis); // an edge runs along one axis
    gmsh::model::mesh::setTransfiniteCurve(curve, n[axis] + 1);
  }
  for (const int surface : entities(2)) {
    gmsh::model::mesh::setTransfiniteSurface(surface);
    gmsh::model::mesh::setRecombine(2, surface);
  }
  gmsh::model::mesh::setTransfiniteVolume(volume);
  name_faces(body.name, 0.5 * (box.min + box.max));
  return {};
}

} // namespace sphfem::mesher
