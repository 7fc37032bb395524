// Test helpers for coupling: bodies meshed by the product's reader and mesher from case text,
// then coupled here — attachments and contact pairs added to the Case, and the background
// nodes and interface flags computed by brute force from METHOD.md §4.1's definition,
// independently of the mesher's own tagging.
#pragma once

#include "mesher/mesher.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/time/simulation.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <string>

namespace sphfem::test {

// Nodes on the boundary of body `body`'s hex mesh: those of faces that belong to one element.
inline std::set<Index> surface_nodes(const Model& m, int body) {
  static constexpr int faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                      {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  std::map<std::array<Index, 4>, int> count;
  for (std::size_t e = 0; e < m.hex_e.size(); ++e)
    if (m.body_e[e] == body)
      for (const auto& f : faces) {
        std::array<Index, 4> key{m.hex_e[e][f[0]], m.hex_e[e][f[1]], m.hex_e[e][f[2]],
                                 m.hex_e[e][f[3]]};
        std::sort(key.begin(), key.end());
        ++count[key];
      }
  std::set<Index> out;
  for (const auto& [key, n] : count)
    if (n == 1)
      out.insert(key.begin(), key.end());
  return out;
}

// Adds background nodes (with h and spacing) and interface flags for c's couplings.
inline void tag_coupling(const Case& c, Model& m) {
  std::map<Index, std::pair<double, double>> background; // node → (h, spacing)
  for (const AttachSpec& a : c.attachments) {
    const int fem = c.body_index(a.fem_body), sph = c.body_index(a.sph_body);
    double h_max = 0;
    for (Index i = 0; i < m.particle_count(); ++i)
      if (m.body_p[i] == sph)
        h_max = std::max(h_max, m.h_p[i]);
    for (Index node = 0; node < m.node_count(); ++node) {
      if (m.body_n[node] != fem)
        continue;
      for (Index i = 0; i < m.particle_count(); ++i)
        if (m.body_p[i] == sph && (m.x_p[i] - m.x_n[node]).norm() < 2.0 * h_max) {
          background[node] = {h_max, m.spacing_b[sph]};
          break;
        }
    }
  }
  for (const ContactSpec& contact : c.contacts)
    for (const std::string& name : contact.bodies) {
      const int body = c.body_index(name);
      const BodySpec& spec = c.bodies[body];
      if (spec.method == Method::Fem)
        for (Index node : surface_nodes(m, body))
          background.try_emplace(node, spec.h_factor * spec.element_size, spec.element_size);
    }
  m.background_nodes.clear();
  m.h_background.clear();
  m.spacing_background.clear();
  for (const auto& [node, hs] : background) {
    m.background_nodes.push_back(node);
    m.h_background.push_back(hs.first);
    m.spacing_background.push_back(hs.second);
  }
  m.interface_p.assign(m.particle_count(), 0);
  for (Index i = 0; i < m.particle_count(); ++i)
    for (std::size_t k = 0; k < m.background_nodes.size(); ++k)
      if ((m.x_p[i] - m.x_n[m.background_nodes[k]]).norm() < m.h_p[i] + m.h_background[k])
        m.interface_p[i] = 1;
}

struct Coupled {
  Case spec;
  Model model;

  // yaml: a case without couplings; attachments and contacts are added before tagging.
  Coupled(const std::string& yaml, std::vector<AttachSpec> attach,
          std::vector<ContactSpec> contacts = {})
      : spec(read_case_text(yaml, "test.yaml")), model(mesh_case(spec)) {
    spec.attachments = std::move(attach);
    spec.contacts = std::move(contacts);
    tag_coupling(spec, model);
  }
};

} // namespace sphfem::test
