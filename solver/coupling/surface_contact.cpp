#include "solver/coupling/surface_contact.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/coupling/ignored_overlap.hpp"
#include "solver/coupling/quad_projection.hpp"
#include "solver/fem/surface_faces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphfem {
namespace {

// One slave's or row's part of ContactTotals.
struct ContactTerm {
  double friction_power = 0; // W
  double omega2 = 0;         // 1/s²
};

// The friction power of term(k), k < count, summed exactly, and the largest ω², in parallel.
template <class Term> ContactTotals contact_totals(Index count, Term term) {
  ContactTotals totals;
#pragma omp parallel if (count > parallel_min_items)
  {
    ContactTotals mine;
#pragma omp for schedule(static) nowait
    for (Index k = 0; k < count; ++k) {
      const ContactTerm t = term(k);
      mine.friction_power.add(t.friction_power);
      mine.omega2 = std::max(mine.omega2, t.omega2);
    }
#pragma omp critical(sphfem_contact_totals)
    totals += mine;
  }
  return totals;
}

// Faces may stretch this much before a slave in contact could lie beyond the corners' reach.
constexpr double stretch_allowance = 1.25;

// A pair counts in the stable step from this fraction of the slave's size ℓ before contact: it
// can close that gap within a step only beyond the speed of sound.
constexpr double near_fraction = 0.5;

// A node meets a face unless the face's normal lies within 60° of the node's own outward normal:
// two bodies meeting edge on edge (equal bars) then do not see each other's side faces.
constexpr double facing_limit = 0.5;

// A change of a slave's signed distance beyond what the bodies' motion explains by this factor
// (and by this fraction of the slave's size, for round-off) is a change of the surface.
constexpr double motion_factor = 2.0;
constexpr double motion_slack = 1e-3;

double quad_area(const std::array<Vec3, 4>& x) {
  return 0.5 * (x[2] - x[0]).cross(x[3] - x[1]).norm();
}

// The friction force on a slave pressed with |F_n| = normal and moving at v_rel relative to its
// partner, and its dissipated power.
struct Friction {
  Vec3 force = Vec3::Zero();
  double power = 0;
};
Friction coulomb(double mu, double normal, const Vec3& n, const Vec3& v_rel, double m_eff,
                 double dt) {
  if (mu <= 0 || dt <= 0)
    return {};
  const Vec3 v_t = v_rel - v_rel.dot(n) * n;
  const double speed = v_t.norm();
  if (speed == 0)
    return {};
  const double magnitude = std::min(mu * normal, 0.5 * m_eff * speed / dt);
  return {(-magnitude / speed) * v_t, magnitude * speed};
}

} // namespace

SurfaceContact::SurfaceContact(const Case& c, const Model& model, const Particles& p,
                               const BackgroundParticles& background, const HexElements& elements)
    : bodies_(static_cast<int>(c.bodies.size())) {
  pair_of_.assign(static_cast<std::size_t>(bodies_) * bodies_, -1);
  in_pair_.assign(bodies_, 0);
  sphere_partner_.assign(bodies_, 0);
  face_partner_.assign(bodies_, 0);
  cut_.resize(bodies_);
  for (const BodySpec& body : c.bodies)
    names_.push_back(body.name);
  for (const ContactSpec& spec : c.contacts) {
    if (spec.model != ContactModel::Surface)
      continue;
    const int a = c.body_index(spec.bodies[0]), b = c.body_index(spec.bodies[1]);
    pair_of_[a * bodies_ + b] = pair_of_[b * bodies_ + a] = static_cast<int>(pairs_.size());
    pairs_.push_back({spec.penalty, spec.friction});
    for (const auto& [self, other] : {std::pair{a, b}, std::pair{b, a}}) {
      in_pair_[self] = 1;
      const bool other_fem = c.bodies[other].method == Method::Fem;
      (other_fem ? face_partner_ : sphere_partner_)[self] = 1;
      if (other_fem && std::ranges::find(fem_bodies_, other) == fem_bodies_.end())
        fem_bodies_.push_back(other);
    }
  }
  if (pairs_.empty())
    return;
  std::ranges::sort(fem_bodies_);
  for (const BoundaryConditionSpec& bc : c.boundary_conditions)
    if (bc.type == BoundaryType::Symmetry)
      if (const auto it = model.face_sets.find(bc.body + "/" + bc.face);
          it != model.face_sets.end())
        cut_[c.body_index(bc.body)].insert(cut_[c.body_index(bc.body)].end(), it->second.begin(),
                                           it->second.end());
  for (const int body : fem_bodies_)
    erodes_ = erodes_ || c.material(c.bodies[body].material).erosion;
  background_of_node_.assign(model.node_count(), -1);
  x0_.resize(static_cast<std::size_t>(background.size()));
  for (Index k = 0; k < background.size(); ++k) {
    background_of_node_[background.node(k)] = k;
    x0_[k] = p.x0_p[p.background_row(k)];
  }
  build_faces(p, elements);

  // A slave within contact range of a face lies within D/2 + R of the face's nearest corner (D
  // its longest diagonal); the neighbour lists hold it if that is below h_corner + h_slave.
  std::vector<double> slack(bodies_, std::numeric_limits<double>::infinity()); // min h − R
  for (Index i = 0; i < p.rows(); ++i)
    if (in_pair_[p.body_p[i]])
      slack[p.body_p[i]] =
          std::min(slack[p.body_p[i]], p.h_p[i] - (i < p.real ? 0.5 * p.dp_p[i] : 0.0));
  for (const Face& face : faces_) {
    std::array<Vec3, 4> x;
    double h = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 4; ++a) {
      x[a] = p.x0_p[face.rows[a]];
      h = std::min(h, p.h_p[face.rows[a]]);
    }
    const double half_diagonal = 0.5 * std::max((x[2] - x[0]).norm(), (x[3] - x[1]).norm());
    double partner_slack = std::numeric_limits<double>::infinity();
    for (int other = 0; other < bodies_; ++other)
      if (pair_index(face.body, other) >= 0)
        partner_slack = std::min(partner_slack, slack[other]);
    const double needed = stretch_allowance * half_diagonal - partner_slack;
    SPHFEM_CHECK(h >= needed, "contact: the surface contact of '", names_[face.body],
                 "' finds its candidates through its background particles, whose h must reach ",
                 stretch_allowance, " × half its faces' diagonal less its partners' h − R: h ≥ ",
                 needed, " m, got ", h, " m; raise the body's h_factor");
  }
}

bool SurfaceContact::slave(const Particles& p, Index i) const {
  if (!face_partner_[p.body_p[i]])
    return false;
  return i < p.real || area_[p.background_particle(i)] > 0;
}

Index SurfaceContact::eroded_count(const HexElements& elements) const {
  if (!erodes_)
    return 0;
  Index count = 0;
  for (Index e = 0; e < elements.size(); ++e)
    count += elements.eroded_e[e] && std::ranges::binary_search(fem_bodies_, elements.body_e[e]);
  return count;
}

void SurfaceContact::build_faces(const Particles& p, const HexElements& elements) {
  faces_.clear();
  area_.assign(x0_.size(), 0.0);
  thickness_.assign(x0_.size(), 0.0);
  normal_.assign(x0_.size(), Vec3::Zero());
  for (const int body : fem_bodies_)
    for (const SurfaceFace& surface :
         surface_faces(elements.nodes_e, elements.body_e, body, elements.eroded_e, cut_[body])) {
      Face face{{}, {}, body, 0};
      std::array<Vec3, 4> x0;
      for (int a = 0; a < 4; ++a) {
        face.background[a] = background_of_node_[surface.nodes[a]];
        SPHFEM_CHECK(face.background[a] >= 0, "contact: node ", surface.nodes[a], " of body '",
                     names_[body],
                     "' lies on its surface but carries no background particle: re-mesh");
        x0[a] = x0_[face.background[a]];
      }
      const double area = quad_area(x0);
      face.depth = elements.V0_e[surface.element] / area;
      for (const Index k : face.background) {
        area_[k] += 0.25 * area;
        thickness_[k] += 0.25 * area * face.depth;
      }
      faces_.push_back(face);
    }
  locate_faces(p);
  for (std::size_t k = 0; k < area_.size(); ++k)
    if (area_[k] > 0)
      thickness_[k] /= area_[k];
  eroded_seen_ = eroded_count(elements);
  built_for_ = -1;
}

void SurfaceContact::build_candidates(Particles& p, const NeighbourList& list) {
  // Every slave in a corner's list is a candidate of the face: (slave, face) pairs, sorted.
  found_.clear();
  const Index rows = p.rows();
  for (Index f = 0; f < static_cast<Index>(faces_.size()); ++f) {
    const Face& face = faces_[f];
    if (!face.held())
      continue; // far from this rank's rows: no slave it evaluates meets it
    for (const Index corner : face.rows)
      for (const Index j : list.of(corner))
        if (j < rows && pair_index(p.body_p[j], face.body) >= 0 && slave(p, j))
          found_.emplace_back(j, f);
  }
  std::ranges::sort(found_);
  found_.erase(std::unique(found_.begin(), found_.end()), found_.end());

  candidates_.resize(found_.size());
  slave_rows_.clear();
  slave_offsets_.clear();
  slave_of_row_.assign(rows, -1);
  for (std::size_t k = 0; k < found_.size(); ++k) {
    const auto [row, f] = found_[k];
    if (slave_rows_.empty() || slave_rows_.back() != row) {
      slave_of_row_[row] = static_cast<Index>(slave_rows_.size());
      slave_rows_.push_back(row);
      slave_offsets_.push_back(static_cast<Index>(k));
    }
    candidates_[k] = Candidate{row, f, Vec3::Zero(), {}, 0, 0};
  }
  slave_offsets_.push_back(static_cast<Index>(found_.size()));
  // Rows that are no slaves now forget their distance: if they come back, they come back new.
  for (Index i = 0; i < rows; ++i)
    if (slave_of_row_[i] < 0) {
      p.contact_s_p[i] = std::numeric_limits<double>::quiet_NaN();
      p.ignored_overlap_p[i] = 0;
    }

  // The face corners' entries, grouped by background row in candidate order (counting sort).
  master_offsets_.assign(static_cast<std::size_t>(p.background) + 1, 0);
  for (const Candidate& c : candidates_)
    for (const Index row : faces_[c.face].rows)
      ++master_offsets_[row - p.real + 1];
  for (Index k = 0; k < p.background; ++k)
    master_offsets_[k + 1] += master_offsets_[k];
  master_entries_.resize(master_offsets_.back());
  cursor_.assign(master_offsets_.begin(), master_offsets_.end() - 1);
  for (Index c = 0; c < static_cast<Index>(candidates_.size()); ++c)
    for (int a = 0; a < 4; ++a)
      master_entries_[cursor_[faces_[candidates_[c].face].rows[a] - p.real]++] = 4 * c + a;
  ++candidate_builds_;
}

void SurfaceContact::share(const Particles& p, const ContactRanks& ranks) {
  // A slave's forces reach its own row and its candidate faces' corners: this rank evaluates it
  // if one of them is its own. It reads the slave, those faces, and for a node the faces around
  // it (its normal).
  const auto& owns = ranks.owns;
  evaluated_.assign(slave_rows_.size(), 0);
  std::vector<unsigned char> read(p.rows(), 0), normal_read(p.background, 0);
  for (std::size_t s = 0; s < slave_rows_.size(); ++s) {
    const Index i = slave_rows_[s];
    bool reached = owns[i];
    for (Index c = slave_offsets_[s]; c < slave_offsets_[s + 1]; ++c)
      for (const Index row : faces_[candidates_[c].face].rows)
        reached = reached || owns[row];
    if (!reached)
      continue;
    evaluated_[s] = 1;
    read[i] = 1;
    for (Index c = slave_offsets_[s]; c < slave_offsets_[s + 1]; ++c)
      for (const Index row : faces_[candidates_[c].face].rows)
        read[row] = 1;
    if (i >= p.real)
      normal_read[i - p.real] = 1;
  }
  for (const Face& face : faces_) {
    const bool around = std::ranges::any_of(
        face.rows, [&](Index row) { return row >= p.real && normal_read[row - p.real] != 0; });
    if (!around)
      continue;
    SPHFEM_CHECK(face.held(), "contact: a face around a slave evaluated here has a corner this "
                              "rank does not hold (internal error)");
    for (const Index row : face.rows)
      read[row] = 1;
  }
  std::vector<Index> rows;
  for (Index i = 0; i < p.rows(); ++i)
    if (read[i] && !owns[i])
      rows.push_back(i);
  ranks.read_also(rows);
}

ContactTotals SurfaceContact::spheres(Particles& p, const NeighbourList& list, double dt,
                                      const ContactRanks* ranks) const {
  // Each particle gathers its own pairs (race-free); each pair's energy and power count half in
  // each of its two rows — so a pair with a mirror image (no row of its own) counts half: its
  // mirror pair, the other half, lies outside the modelled part.
  const IndexRange rows = IndexRange::of(ranks != nullptr ? ranks->own : nullptr, p.size());
  return contact_totals(rows.count, [&](Index k) {
    const Index i = rows[k];
    const int body = p.body_p[i];
    if (!sphere_partner_[body])
      return ContactTerm{};
    const int row = body * bodies_;
    const Vec3 xi = p.x_p[i], vi = p.v_p[i];
    const double R_i = 0.5 * p.dp_p[i], m_i = p.m_p[i], V_i = m_i / p.rho0_p[i];
    Vec3 f = Vec3::Zero();
    ContactTerm sums;
    double energy = 0;
    double stiffness = 0; // Σ k (1/m_i + 1/m_j) of the springs near contact
    for (const Index j : list.of(i)) {
      if (!p.real_like(j))
        continue;
      const int k_pair = pair_of_[row + p.body_p[j]];
      if (k_pair < 0)
        continue;
      const Vec3 x_ij = xi - p.x_p[j];
      const double r = x_ij.norm();
      const double size = 0.5 * (p.dp_p[i] + p.dp_p[j]);
      const double gap = r - R_i - 0.5 * p.dp_p[j];
      if (gap >= near_fraction * size || r == 0)
        continue;
      const Pair& pair = pairs_[k_pair];
      const double V_j = p.m_p[j] / p.rho0_p[j];
      const double k = pair.modulus * (2 * V_i * V_j / (V_i + V_j)) / (size * size);
      stiffness += k * (1 / m_i + 1 / p.m_p[j]);
      if (gap >= 0)
        continue;
      const Vec3 n = x_ij / r;
      const double normal = -k * gap;
      const Friction friction =
          coulomb(pair.friction, normal, n, vi - p.v_p[j], m_i * p.m_p[j] / (m_i + p.m_p[j]), dt);
      const Vec3 f_ij = normal * n + friction.force;
      f += f_ij;
      if (j >= p.rows())
        p.fm_p[i] += f_ij; // contact with a mirror image: part of the planes' reaction
      energy += 0.25 * k * gap * gap;
      sums.friction_power += 0.5 * friction.power;
    }
    p.f_p[i] += f;
    p.fc_p[i] += f;
    p.phi_p[i] += energy;
    if (f != Vec3::Zero())
      p.xsph_p[i].setZero(); // drifts with v while pressed: the spring's energy then balances
    sums.omega2 = stiffness;
    return sums;
  });
}

void SurfaceContact::update_normals(const Particles& p) {
  // Area-weighted: Σ over a node's faces of ½ (x2 − x0) × (x3 − x1), normalised.
  std::fill(normal_.begin(), normal_.end(), Vec3::Zero());
  for (const Face& face : faces_) {
    if (!face.held())
      continue; // nor are its corners' normals read here
    const auto& x = p.x_p;
    const Vec3 n =
        0.5 * (x[face.rows[2]] - x[face.rows[0]]).cross(x[face.rows[3]] - x[face.rows[1]]);
    for (const Index k : face.background)
      normal_[k] += n;
  }
  for (Vec3& n : normal_)
    if (const double length = n.norm(); length > 0)
      n /= length;
}

ContactTotals SurfaceContact::segments(Particles& p, double dt, const ContactRanks* ranks) {
  // Each slave chooses its face and writes only its own candidates (race-free). Several ranks
  // may evaluate a slave; its owner counts its friction.
  return contact_totals(static_cast<Index>(slave_rows_.size()), [&](Index s) {
    if (ranks != nullptr && !evaluated_[s])
      return ContactTerm{};
    const Index i = slave_rows_[s];
    const bool particle = i < p.real;
    const double R = particle ? 0.5 * p.dp_p[i] : 0.0;
    const Index node_k = particle ? -1 : p.background_particle(i); // a node's
    const double size = particle ? p.dp_p[i] : thickness_[node_k];
    const double area = particle ? p.m_p[i] / (p.rho0_p[i] * size) : area_[node_k];
    const Vec3 xi = p.x_p[i];
    const auto lower_bound = [](const std::array<Vec3, 4>& x, const Vec3& point) {
      const Vec3 centre = 0.25 * (x[0] + x[1] + x[2] + x[3]);
      double reach = 0;
      for (const Vec3& corner : x)
        reach = std::max(reach, (corner - centre).norm());
      return (point - centre).norm() - reach; // no point of the face lies nearer
    };
    const auto corners = [&](Index face) {
      std::array<Vec3, 4> x;
      for (int a = 0; a < 4; ++a)
        x[a] = p.x_p[faces_[face].rows[a]];
      return x;
    };
    // A node does not meet faces turned its own way (their normal within 60° of its own).
    const auto facing = [&](const std::array<Vec3, 4>& x) {
      const Vec3 n = (x[2] - x[0]).cross(x[3] - x[1]);
      return normal_[node_k].dot(n) < facing_limit * n.norm();
    };
    // The nearest point of the other body's surface among the candidate faces.
    Index best = -1;
    QuadPoint nearest;
    for (Index c = slave_offsets_[s]; c < slave_offsets_[s + 1]; ++c) {
      Candidate& candidate = candidates_[c];
      candidate.force.setZero();
      candidate.stiffness = 0;
      const std::array<Vec3, 4> x = corners(candidate.face);
      if (!particle && !facing(x))
        continue;
      const double bound = lower_bound(x, xi);
      if (bound > R + near_fraction * size || (best >= 0 && bound >= nearest.distance))
        continue;
      const QuadPoint q = nearest_on_quad(x, xi);
      if (best < 0 || q.distance < nearest.distance) {
        best = c;
        nearest = q;
      }
    }
    if (best < 0)
      return ContactTerm{};
    // On an edge or a corner: the faces that share the nearest point give the side (the sum of
    // their normals there). A node that does not see one of them meets the body edge on edge:
    // the face it sees holds it by its plane.
    Vec3 outward = Vec3::Zero();
    bool held = false;
    if (!nearest.inside && nearest.distance > 0) {
      const double shared = 1e-9 * size;
      for (Index c = slave_offsets_[s]; c < slave_offsets_[s + 1]; ++c) {
        const std::array<Vec3, 4> x = corners(candidates_[c].face);
        if (lower_bound(x, nearest.x) > shared)
          continue;
        if (const QuadPoint q = nearest_on_quad(x, nearest.x); q.distance <= shared) {
          if (particle || facing(x))
            outward += q.normal;
          else
            held = true;
        }
      }
    }
    const SignedGap g = signed_gap(nearest, xi, outward, held);
    const Vec3 n = g.gradient;
    Candidate& chosen = candidates_[best];
    const Face& face = faces_[chosen.face];
    // The overlap a change of the surface added since the last step is ignored: the slave and
    // the face's nodes moved s by at most Δt (|v_s| + max |v_a|), by Δt ∇s · v_rel to first order.
    const Vec3 v_slave = particle ? p.u_p[i] : p.v_p[i]; // what moved it in the last drift
    Vec3 v_rel = v_slave;
    double face_speed = 0;
    for (int a = 0; a < 4; ++a) {
      v_rel -= nearest.N[a] * p.v_p[face.rows[a]];
      face_speed = std::max(face_speed, p.v_p[face.rows[a]].norm());
    }
    const double slave_speed = std::max(v_slave.norm(), p.v_p[i].norm());
    const double moved = motion_factor * dt * (slave_speed + face_speed) + motion_slack * size;
    const double previous = dt > 0 ? p.contact_s_p[i] : g.s; // at the start: no change yet
    const double ignored = ignored_overlap(previous, previous + dt * n.dot(v_rel), g.s, moved,
                                           R - g.s, p.ignored_overlap_p[i]);
    p.contact_s_p[i] = g.s;
    p.ignored_overlap_p[i] = ignored;
    const double gap = g.s - R + ignored;
    if (gap >= near_fraction * size || g.s < -face.depth)
      return ContactTerm{};
    const Pair& pair = pairs_[pair_index(p.body_p[i], face.body)];
    const double k = pair.modulus * area / size;
    double inverse_mass = 1 / p.m_p[i]; // 1/m_s + Σ N_a²/m_a: the pair's effective mass
    Vec3 v_face = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      inverse_mass += nearest.N[a] * nearest.N[a] / p.m_p[face.rows[a]];
      v_face += nearest.N[a] * p.v_p[face.rows[a]];
    }
    chosen.N = nearest.N;
    chosen.stiffness = k;
    chosen.face_inverse_mass = inverse_mass - 1 / p.m_p[i];
    ContactTerm sums;
    sums.omega2 = k * inverse_mass;
    if (gap >= 0)
      return sums;
    const double normal = -k * gap;
    const Friction friction =
        coulomb(pair.friction, normal, n, p.v_p[i] - v_face, 1 / inverse_mass, dt);
    chosen.force = normal * n + friction.force;
    p.phi_p[i] += 0.5 * k * gap * gap;
    if (ranks == nullptr || ranks->owns[i])
      sums.friction_power = friction.power;
    return sums;
  });
}

ContactTotals SurfaceContact::gather(Particles& p, const ContactRanks* ranks) const {
  // Each row sums its own entries — as a slave, then as a face corner — in a fixed order.
  const IndexRange rows = IndexRange::of(ranks != nullptr ? ranks->own : nullptr, p.rows());
  return contact_totals(rows.count, [&](Index k) {
    const Index i = rows[k];
    if (!in_pair_[p.body_p[i]])
      return ContactTerm{};
    Vec3 f = Vec3::Zero();
    if (const Index s = slave_of_row_[i]; s >= 0)
      for (Index c = slave_offsets_[s]; c < slave_offsets_[s + 1]; ++c)
        f += candidates_[c].force;
    // ω² of the springs holding this entity: its own as a slave, k (1/m_i + Σ N_a²/m_a), and
    // those of the slaves pressing on it as a face node, Σ k N² (1/m_i + 1/m_slave).
    const double inverse_mass = 1 / p.m_p[i];
    double omega2 = 0;
    if (const Index s = slave_of_row_[i]; s >= 0)
      for (Index c = slave_offsets_[s]; c < slave_offsets_[s + 1]; ++c)
        omega2 += candidates_[c].stiffness * (inverse_mass + candidates_[c].face_inverse_mass);
    if (i >= p.real)
      for (Index e = master_offsets_[i - p.real]; e < master_offsets_[i - p.real + 1]; ++e) {
        const Candidate& c = candidates_[master_entries_[e] / 4];
        const double N = c.N[master_entries_[e] % 4];
        f -= N * c.force;
        omega2 += c.stiffness * N * N * (inverse_mass + 1 / p.m_p[c.slave]);
      }
    p.f_p[i] += f;
    p.fc_p[i] += f;
    if (i < p.real && f != Vec3::Zero())
      p.xsph_p[i].setZero(); // a pressed particle drifts with v, as in spheres()
    ContactTerm sums;
    sums.omega2 = omega2;
    return sums;
  });
}

void SurfaceContact::locate_faces(const Particles& p) {
  for (Face& face : faces_)
    for (int a = 0; a < 4; ++a)
      face.rows[a] = p.background_row(face.background[a]);
}

ContactTotals SurfaceContact::apply(Particles& p, const NeighbourList& list, long long lists,
                                    const HexElements& elements, double dt,
                                    const ContactRanks* ranks) {
  if (pairs_.empty())
    return {};
  if (eroded_seen_ < 0 || eroded_count(elements) != eroded_seen_)
    build_faces(p, elements);
  if (built_for_ != lists) {
    locate_faces(p); // the rows may have been laid anew with the lists
    build_candidates(p, list);
    built_for_ = lists;
  }
  if (ranks != nullptr && shared_for_ != std::pair{candidate_builds_, ranks->shares}) {
    share(p, *ranks);
    shared_for_ = {candidate_builds_, ranks->shares};
  }
  ContactTotals totals = spheres(p, list, dt, ranks);
  if (!faces_.empty())
    update_normals(p);
  totals += segments(p, dt, ranks);
  totals += gather(p, ranks);
  return totals;
}

} // namespace sphfem
