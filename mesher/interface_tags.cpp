// Interface tagging (METHOD.md §4.1), in the initial configuration:
// - attachment (FE body f, SPH body s, METHOD.md §4.2): every node of f closer than 2·h_s to a
//   particle of s gets a background particle with s's h_s = h_factor·Δp and spacing Δp;
// - contact pair (METHOD.md §4.3): each FE body of the pair gives its surface nodes (on hexahedron
//   faces that belong to one element only, its symmetry faces excepted: the body goes on beyond
//   them) a background particle with h = h_factor·element_size and spacing element_size, unless
//   an attachment tagged the node (attachment values win);
// - a node that several attachments tag keeps the largest h (then the largest spacing), so the
//   order of the case's lists does not matter;
// - interface_p[i] = 1 if some background particle b has |x_i − x_b| < h_i + h_b (= 2·h_ij).
// "Closer than" is strict: the cubic B-spline vanishes at r = 2h. Near-point searches use a
// cell grid (mesher/point_grid.hpp). Verified by tests/mesher/interface_tags_test.cpp.
#include "mesher/interface_tags.hpp"

#include "mesher/point_grid.hpp"
#include "solver/core/error.hpp"

#include <algorithm>
#include <array>

namespace sphfem::mesher {
namespace {

// A node's tag while tagging: h = 0 means none.
struct Tag {
  double h = 0, spacing = 0;
  bool attached = false;
};

int body_id(const Case& c, const std::string& name) {
  const int id = c.body_index(name);
  SPHFEM_CHECK(id >= 0, "interface tags: no body '", name, "'");
  return id;
}

// Attachment of FE body `fem` to SPH body `sph`.
void tag_attachment(const Model& m, const BodySpec& sph, int fem, int sph_id,
                    std::vector<Tag>& tags) {
  const double h = sph.h_factor * sph.spacing;
  std::vector<Vec3> particles;
  for (std::size_t p = 0; p < m.x_p.size(); ++p)
    if (m.body_p[p] == sph_id)
      particles.push_back(m.x_p[p]);
  const double reach = 2 * h;
  const PointGrid grid(particles, reach);
  for (std::size_t n = 0; n < m.x_n.size(); ++n) {
    if (m.body_n[n] != fem)
      continue;
    const Vec3& x = m.x_n[n];
    if (!grid.any_near(x, [&](Index j) { return (grid.point(j) - x).norm() < reach; }))
      continue;
    Tag& tag = tags[n];
    if (!tag.attached || std::pair(h, sph.spacing) > std::pair(tag.h, tag.spacing))
      tag = {h, sph.spacing, true};
  }
}

// The quads of the body's faces that carry a symmetry condition.
std::vector<Quad> symmetry_faces(const Model& m, const Case& c, const std::string& body) {
  std::vector<Quad> quads;
  for (const BoundaryConditionSpec& bc : c.boundary_conditions)
    if (bc.type == BoundaryType::Symmetry && bc.body == body)
      if (const auto it = m.face_sets.find(body + "/" + bc.face); it != m.face_sets.end())
        quads.insert(quads.end(), it->second.begin(), it->second.end());
  return quads;
}

void tag_contact_body(const Model& m, const Case& c, const BodySpec& body, int id,
                      std::vector<Tag>& tags) {
  for (const Index n : surface_nodes(m, id, symmetry_faces(m, c, body.name)))
    if (!tags[static_cast<std::size_t>(n)].attached)
      tags[static_cast<std::size_t>(n)] = {body.h_factor * body.element_size, body.element_size,
                                           false};
}

// interface_p from the background particles already in `m`.
std::vector<int> interface_flags(const Model& m) {
  std::vector<int> flags(m.x_p.size(), 0);
  if (m.background_nodes.empty() || m.x_p.empty())
    return flags;
  std::vector<Vec3> x_b;
  for (const Index n : m.background_nodes)
    x_b.push_back(m.x_n[static_cast<std::size_t>(n)]);
  const double h_b_max = *std::ranges::max_element(m.h_background);
  const double h_p_max = *std::ranges::max_element(m.h_p);
  const PointGrid grid(x_b, h_p_max + h_b_max);
  for (std::size_t i = 0; i < m.x_p.size(); ++i) {
    const Vec3& x = m.x_p[i];
    const double h_i = m.h_p[i];
    flags[i] = grid.any_near(x, [&](Index b) {
      return (grid.point(b) - x).norm() < h_i + m.h_background[static_cast<std::size_t>(b)];
    });
  }
  return flags;
}

} // namespace

std::vector<Index> surface_nodes(const Model& m, int body_id, const std::vector<Quad>& cut) {
  // Hexahedron faces by local node (gmsh order); a face is identified by its sorted nodes.
  static constexpr int faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                      {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  std::vector<std::array<Index, 4>> keys;
  for (std::size_t e = 0; e < m.hex_e.size(); ++e) {
    if (m.body_e[e] != body_id)
      continue;
    for (const auto& face : faces) {
      std::array<Index, 4> key;
      for (int k = 0; k < 4; ++k)
        key[k] = m.hex_e[e][face[k]];
      std::ranges::sort(key);
      keys.push_back(key);
    }
  }
  std::ranges::sort(keys);
  std::vector<std::array<Index, 4>> cut_keys;
  for (const Quad& q : cut) {
    std::array<Index, 4> key{q[0], q[1], q[2], q[3]};
    std::ranges::sort(key);
    cut_keys.push_back(key);
  }
  std::ranges::sort(cut_keys);
  std::vector<Index> nodes;
  for (std::size_t f = 0; f < keys.size();) {
    std::size_t same = f + 1;
    while (same < keys.size() && keys[same] == keys[f])
      ++same;
    if (same == f + 1 && !std::ranges::binary_search(cut_keys, keys[f]))
      nodes.insert(nodes.end(), keys[f].begin(), keys[f].end());
    f = same;
  }
  std::ranges::sort(nodes);
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

void tag_interfaces(Model& m, const Case& c) {
  SPHFEM_CHECK(m.body_n.size() == m.x_n.size() && m.body_p.size() == m.x_p.size() &&
                   m.h_p.size() == m.x_p.size(),
               "interface tags: the model's arrays do not match");
  std::vector<Tag> tags(m.x_n.size());
  for (const AttachSpec& attach : c.attachments) {
    const int sph = body_id(c, attach.sph_body);
    tag_attachment(m, c.bodies[static_cast<std::size_t>(sph)], body_id(c, attach.fem_body), sph,
                   tags);
  }
  for (const ContactSpec& contact : c.contacts)
    for (const std::string& name : contact.bodies) {
      const int id = body_id(c, name);
      if (c.bodies[static_cast<std::size_t>(id)].method == Method::Fem)
        tag_contact_body(m, c, c.bodies[static_cast<std::size_t>(id)], id, tags);
    }
  m.background_nodes.clear();
  m.h_background.clear();
  m.spacing_background.clear();
  for (std::size_t n = 0; n < tags.size(); ++n)
    if (tags[n].h > 0) {
      m.background_nodes.push_back(static_cast<Index>(n));
      m.h_background.push_back(tags[n].h);
      m.spacing_background.push_back(tags[n].spacing);
    }
  m.interface_p = interface_flags(m);
}

} // namespace sphfem::mesher
