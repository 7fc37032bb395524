// Copies gmsh's mesh of one body into the Model: maps gmsh node tags to contiguous indices,
// orders hexes to positive volume and orients named-face quads outwards using the hexes
// they bound. Verified by tests/mesher/mesher_test.cpp.
#include "mesher/gmsh_body.hpp"
#include "solver/core/error.hpp"

#include <Eigen/Geometry>
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <span>

namespace sphfem::mesher {
namespace {

constexpr int gmsh_quad = 3;
constexpr int gmsh_hex = 5;

// Faces of a positive-volume hex in gmsh order, each with its right-hand normal outwards.
constexpr std::array<Quad, 6> hex_faces{
    {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};

// gmsh node tag → model node index (−1: not a hex node).
using TagMap = std::vector<Index>;

std::vector<std::size_t> hex_node_tags() {
  std::vector<int> types;
  gmsh::model::mesh::getElementTypes(types, 3);
  SPHFEM_CHECK(types == std::vector<int>{gmsh_hex},
               "gmsh produced no hexahedra or other volume elements too");
  std::vector<std::size_t> element_tags, node_tags;
  gmsh::model::mesh::getElementsByType(gmsh_hex, element_tags, node_tags);
  return node_tags;
}

// Adds the nodes the hexes use, in increasing gmsh tag order, placed in space.
TagMap append_nodes(Model& model, int body_id, const Placement& placement,
                    const std::vector<std::size_t>& hex_tags) {
  std::vector<std::size_t> tags;
  std::vector<double> coord, parametric;
  gmsh::model::mesh::getNodes(tags, coord, parametric, -1, -1, false, false);
  const std::size_t max_tag = tags.empty() ? 0 : *std::max_element(tags.begin(), tags.end());
  std::vector<std::size_t> position(max_tag + 1, tags.size());
  for (std::size_t i = 0; i < tags.size(); ++i)
    position[tags[i]] = i;
  std::vector<bool> used(max_tag + 1, false);
  for (const std::size_t tag : hex_tags) {
    SPHFEM_CHECK(tag <= max_tag && position[tag] < tags.size(), "hexahedron uses unknown node ",
                 tag);
    used[tag] = true;
  }
  TagMap index(max_tag + 1, -1);
  for (std::size_t tag = 0; tag <= max_tag; ++tag) {
    if (!used[tag])
      continue;
    index[tag] = model.node_count();
    const Vec3 local = Eigen::Map<const Vec3>(&coord[3 * position[tag]]);
    model.x_n.push_back(placement.rotation * local + placement.origin);
    model.body_n.push_back(body_id);
  }
  return index;
}

// 8·det J at the element centre: the volume of a parallelepiped hex, and its sign in general.
double centre_jacobian(const std::vector<Vec3>& x, const Hex& hex) {
  const auto p = [&](int i) -> const Vec3& { return x[hex[i]]; };
  const Vec3 d_xi = p(1) + p(2) + p(5) + p(6) - p(0) - p(3) - p(4) - p(7);
  const Vec3 d_eta = p(2) + p(3) + p(6) + p(7) - p(0) - p(1) - p(4) - p(5);
  const Vec3 d_zeta = p(4) + p(5) + p(6) + p(7) - p(0) - p(1) - p(2) - p(3);
  return d_xi.dot(d_eta.cross(d_zeta)) / 64.0;
}

void append_hexes(Model& model, int body_id, const std::vector<std::size_t>& hex_tags,
                  const TagMap& index) {
  for (std::size_t e = 0; e < hex_tags.size(); e += 8) {
    Hex hex;
    for (int i = 0; i < 8; ++i)
      hex[i] = index[hex_tags[e + i]];
    model.hex_e.push_back(with_positive_volume(model.x_n, hex));
    model.body_e.push_back(body_id);
  }
}

// The quads of a physical surface group, as model node indices (gmsh's orientation).
std::vector<Quad> group_quads(int group, const TagMap& index) {
  std::vector<int> surfaces;
  gmsh::model::getEntitiesForPhysicalGroup(2, group, surfaces);
  std::vector<Quad> quads;
  for (const int surface : surfaces) {
    std::vector<int> types;
    gmsh::model::mesh::getElementTypes(types, 2, surface);
    SPHFEM_CHECK(types == std::vector<int>{gmsh_quad}, "surface ", surface,
                 " is not meshed with quadrilaterals only");
    std::vector<std::size_t> element_tags, node_tags;
    gmsh::model::mesh::getElementsByType(gmsh_quad, element_tags, node_tags, surface);
    for (std::size_t q = 0; q < node_tags.size(); q += 4) {
      Quad quad;
      for (int i = 0; i < 4; ++i) {
        const std::size_t tag = node_tags[q + i];
        SPHFEM_CHECK(tag < index.size() && index[tag] >= 0, "face node ", tag,
                     " is on no hexahedron");
        quad[i] = index[tag];
      }
      quads.push_back(quad);
    }
  }
  return quads;
}

// The hexes around each node of one body (compressed rows), to find the hex a face bounds.
class NodeHexes {
public:
  NodeHexes(const Model& model, Index first_node, std::size_t first_hex)
      : first_node_(first_node), start_(model.x_n.size() - first_node + 1, 0) {
    const auto hexes = std::span(model.hex_e).subspan(first_hex);
    for (const Hex& hex : hexes)
      for (const Index i : hex)
        ++start_[i - first_node + 1];
    std::partial_sum(start_.begin(), start_.end(), start_.begin());
    hex_.resize(start_.back());
    std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t e = 0; e < hexes.size(); ++e)
      for (const Index i : hexes[e])
        hex_[fill[i - first_node]++] = first_hex + e;
  }
  std::span<const std::size_t> around(Index node) const {
    const std::size_t i = node - first_node_;
    return std::span(hex_).subspan(start_[i], start_[i + 1] - start_[i]);
  }

private:
  Index first_node_;
  std::vector<std::size_t> start_, hex_;
};

Quad sorted(Quad q) {
  std::sort(q.begin(), q.end());
  return q;
}

// The face of the one hex that `quad` bounds, in that hex's outward order.
Quad outward(const Model& model, const NodeHexes& node_hexes, const Quad& quad) {
  const Quad key = sorted(quad);
  std::optional<Quad> found;
  for (const std::size_t e : node_hexes.around(quad[0])) {
    const Hex& hex = model.hex_e[e];
    for (const Quad& local : hex_faces) {
      const Quad face{hex[local[0]], hex[local[1]], hex[local[2]], hex[local[3]]};
      if (sorted(face) != key)
        continue;
      SPHFEM_CHECK(!found, "a named face lies inside the body");
      found = face;
    }
  }
  SPHFEM_CHECK(found, "a named-face quadrilateral bounds no hexahedron");
  return *found;
}

// Every physical surface becomes a face set of outward quads and the node set of its nodes.
void append_sets(Model& model, Index first_node, std::size_t first_hex, const TagMap& index) {
  const NodeHexes node_hexes(model, first_node, first_hex);
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 2);
  for (const auto& [dim, group] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, group, name);
    SPHFEM_CHECK(!model.face_sets.contains(name), "face set '", name, "' already exists");
    std::vector<Quad>& quads = model.face_sets[name];
    std::vector<Index>& nodes = model.node_sets[name];
    for (const Quad& quad : group_quads(group, index)) {
      quads.push_back(outward(model, node_hexes, quad));
      nodes.insert(nodes.end(), quad.begin(), quad.end());
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  }
}

} // namespace

Hex with_positive_volume(const std::vector<Vec3>& x, Hex hex) {
  double volume = centre_jacobian(x, hex);
  if (volume < 0) { // mirror ζ: bottom and top faces both reversed
    hex = {hex[0], hex[3], hex[2], hex[1], hex[4], hex[7], hex[6], hex[5]};
    volume = -volume;
  }
  const double size = (x[hex[6]] - x[hex[0]]).norm();
  SPHFEM_CHECK(volume > 1e-9 * size * size * size, "degenerate hexahedron (nodes ", hex[0], ", ",
               hex[6], ")");
  return hex;
}

void append_mesh(Model& model, int body_id, const Placement& placement) {
  const std::vector<std::size_t> hex_tags = hex_node_tags();
  const std::size_t first_hex = model.hex_e.size();
  const Index first_node = model.node_count();
  const TagMap index = append_nodes(model, body_id, placement, hex_tags);
  append_hexes(model, body_id, hex_tags, index);
  append_sets(model, first_node, first_hex, index);
}

} // namespace sphfem::mesher
