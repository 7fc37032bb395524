// Interface tagging (METHOD.md §4.1), in the initial configuration:
// - attachment (FE body f, SPH body s, METHOD.md §4.2): every node of f closer than 2·h_s to a
//   particle of s gets a background particle with s's h_s = h_factor·Δp and spacing Δp;
// - contact pair (METHOD.md §4.3, docs/contact.md): each FE body of the pair gives its surface
//   nodes (on hexahedron faces that belong to one element only, its symmetry faces excepted: the
//   body goes on beyond them) a background particle with h = h_factor·element_size and spacing
//   element_size, unless an attachment tagged the node (attachment values win); in a surface
//   contact, an FE body whose material erodes gives every node one, since eroded elements
//   expose the nodes behind them;
// - a node that several attachments tag keeps the largest h (then the largest spacing), so the
//   order of the case's lists does not matter;
// - interface_p[i] = 1 if some background particle b has |x_i − x_b| < h_i + h_b (= 2·h_ij).
// "Closer than" is strict: the cubic B-spline vanishes at r = 2h. Near-point searches use a
// cell grid (mesher/point_grid.hpp). Verified by tests/mesher/interface_tags_test.cpp.
#include "mesher/interface_tags.hpp"

#include "mesher/point_grid.hpp"
#include "solver/core/error.hpp"
#include "solver/fem/surface_faces.hpp"

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

void tag_contact_body(const Model& m, const Case& c, const BodySpec& body, int id, bool every_node,
                      std::vector<Tag>& tags) {
  std::vector<Index> nodes;
  if (every_node) {
    for (std::size_t n = 0; n < m.x_n.size(); ++n)
      if (m.body_n[n] == id)
        nodes.push_back(static_cast<Index>(n));
  } else {
    nodes = surface_nodes(m, id, symmetry_faces(m, c, body.name));
  }
  for (const Index n : nodes)
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

bool exposes_inner_nodes(const Case& c, const BodySpec& body) {
  return body.method == Method::Fem && c.material(body.material).erosion;
}

std::vector<Index> surface_nodes(const Model& m, int body_id, const std::vector<Quad>& cut) {
  std::vector<Index> nodes;
  for (const SurfaceFace& face : surface_faces(m.hex_e, m.body_e, body_id, {}, cut))
    nodes.insert(nodes.end(), face.nodes.begin(), face.nodes.end());
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
      const BodySpec& body = c.bodies[static_cast<std::size_t>(id)];
      if (body.method == Method::Fem)
        tag_contact_body(m, c, body, id,
                         contact.model == ContactModel::Surface && exposes_inner_nodes(c, body),
                         tags);
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
