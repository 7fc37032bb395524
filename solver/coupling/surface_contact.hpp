// Surface contact between bodies (`model: surface`, docs/contact.md): a penalty force that starts
// where the bodies' physical surfaces meet, not at the kernel's reach.
// - Hexahedral bodies are their surface faces (fem/surface_faces.hpp), bilinear segments with
//   the current outward normal; their surface nodes (background particles) are points.
// - Particles are spheres of radius R = Δp/2: a cell-centred lattice's outer particles lie Δp/2
//   inside the body's surface, so the spheres reach the surface on a flat face; a sphere of
//   volume Δp³ (R = 0.62 Δp) would start contact 0.12 Δp early on each side.
// Slave–segment pairs: a particle or a surface node of one body against the faces of the other,
// both ways between two hexahedral bodies, so that neither passes through the other's nodes.
// Each slave takes the nearest point of the other body's surface among the faces near it
// (coupling/quad_projection.hpp) and its signed distance s from that surface: on a face, its
// height over the face; on an edge or a corner, ± its distance, on the side the normals of the
// faces sharing the point give (the true signed distance, continuous from face to face and round
// convex and concave edges, so the contact energy has no jumps). A node only meets faces that
// face it (their normal not within 60° of n_node, the mean outward normal of its own surface
// faces): two bodies meeting edge on edge do not see each other's side faces, and a node whose
// nearest point lies on an edge or corner shared with such an unseen face is held by the plane
// of the face it sees (s its height over that plane). The overlap is δ = R − s; slaves deeper than
// the face's element (s < −V0/A0) have passed through and are left alone. Where the surface
// itself changes under a slave (erosion, a face turning into view, a pinched corner), s jumps:
// the overlap such a jump adds is ignored (coupling/ignored_overlap.hpp), so contact creates no
// energy from it.
// Sphere pairs: particles of two particle bodies overlap by δ = R_i + R_j − r_ij.
// Penalty: p = E_c δ / ℓ with E_c the pair's contact modulus (`penalty`, Pa; by default the
// softer P-wave modulus), on the slave's area A: F = k δ n, k = E_c A / ℓ. A particle is its
// cell, ℓ = Δp and A = V/Δp (V = m/ρ0: a lattice's surface particles, of half or a quarter of the
// volume, carry half or a quarter of the area); a node has its tributary area A on its surface
// faces and ℓ the thickness V0/A0 of the elements under them. So k/m ≈ E_c/(ρ ℓ²) for every
// entity — a light corner particle or node is no stiffer for its mass than a whole one — and a
// pressure p presses the surfaces δ = p ℓ / E_c into each other (2.9% of ℓ for steel bars meeting
// at 2 × 200 m/s). Two particles: k = E_c V_ij / Δp_ij², V_ij = 2 V_i V_j / (V_i + V_j), Δp_ij
// their mean spacing. The face's nodes get −N_a F. The energy ½ k δ² is the contact energy of
// the balance (the forces are its exact gradient, including the segment's motion); both forces
// of a pair are equal and opposite, so momentum is conserved to round-off. The forces do work on
// the velocities v; a particle drifts with v + its XSPH correction (METHOD.md §2), so a pressed
// particle would move the spring by a motion its force does no work on: a particle the contact
// pushes drifts with v alone in the next step (its XSPH correction zeroed).
// Friction (`friction: μ`): F_t = −min(μ |F|, ½ m_eff |v_t| / Δt) t̂ against the slave's
// tangential velocity v_t relative to the face (the second bound stops a sticking pair within
// a step without overshoot); its power −F_t · v_t ≥ 0 is dissipated energy in the balance.
// Stable step: each pair within ℓ/2 of contact is a spring k between the slave's mass and the
// face's nodes, ω² = k (1/m_s + Σ N_a²/m_a); an entity held by several springs — its own as a
// slave and those of the slaves pressing on it as a face node (between two meshes, both) — adds
// theirs, k N² (1/m + 1/m_partner) each.
// Candidates come from the neighbour lists: a slave within contact range of a face lies within
// h_a + h_s of one of its corner nodes a when the corners' h is at least ½ the face's diagonal
// (checked at the start). They are collected when the lists are rebuilt, and the faces again
// when elements erode. The energy of each pair is kept on its slave's row (phi_p; a sphere pair
// half on each), so that the contact energy is Σ phi_p.
// Across MPI ranks (coupling/contact_ranks.hpp): every rank holds the same faces and candidates
// (from the whole neighbour list and the whole erosion state) and evaluates the slaves whose
// forces reach its rows — its own, and those pressing on a face with a corner of its own — as
// their owners do; the rows they read join the particle halo. Each row's force is then summed
// as on one process. Verified by tests/coupling/surface_contact_test.cpp and the mpirun runs of
// tests/e2e/mpi_launch_test.cpp.
#pragma once

#include "solver/core/exact_sum.hpp"
#include "solver/coupling/background_particles.hpp"
#include "solver/coupling/contact_ranks.hpp"
#include "solver/io/case.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/hex_elements.hpp"
#include "solver/state/model.hpp"
#include "solver/state/particles.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

namespace sphfem {

// What one evaluation of contact gives besides its forces and its energy (phi_p): over this
// rank's rows and slaves. The friction power is an exact sum (core/exact_sum.hpp), the same bits
// however the slaves are shared among threads and ranks.
struct ContactTotals {
  ExactSum friction_power; // power dissipated by friction now, W
  double omega2 = 0;       // largest squared angular frequency of the contact springs, 1/s²
  ContactTotals& operator+=(const ContactTotals& o) {
    friction_power += o.friction_power;
    omega2 = std::max(omega2, o.omega2);
    return *this;
  }
};

class SurfaceContact {
public:
  SurfaceContact() = default;
  // The case's surface pairs. p: the particle arrays with their background rows (of
  // `background`'s nodes), before any step; elements: the hexahedra (reference volumes).
  SurfaceContact(const Case& c, const Model& model, const Particles& p,
                 const BackgroundParticles& background, const HexElements& elements);

  bool empty() const { return pairs_.empty(); }
  // Drops the faces and candidates collected so far, so that the next apply() collects them
  // again (after a checkpoint was read into the state).
  void forget() { eroded_seen_ = -1, built_for_ = -1; }
  // Adds the contact and friction forces to f_p and fc_p of every row (of this rank's rows:
  // `ranks`, null on one process) and the pairs' energy to phi_p. lists: changes whenever the
  // neighbour lists are made anew (the candidates are then found again); dt: the step just
  // taken (0 at the start: no friction then). Collective when the candidates change.
  ContactTotals apply(Particles& p, const NeighbourList& list, long long lists,
                      const HexElements& elements, double dt, const ContactRanks* ranks = nullptr);
  // Whether the faces follow eroding elements (a distributed run then shares the erosion).
  bool follows_erosion() const { return erodes_; }

private:
  struct Pair {
    double modulus = 0;  // contact modulus E_c, Pa
    double friction = 0; // μ
  };
  struct Face {
    std::array<Index, 4> background; // its nodes' background particles
    std::array<Index, 4> rows;       // and their rows (−1: not held on this rank)
    int body = 0;
    double depth = 0; // its element's thickness V0/A0: deeper slaves have passed through, m
    bool held() const {
      return std::ranges::none_of(rows, [](Index row) { return row < 0; });
    }
  };
  // Per candidate (slave, face): the force on the slave and the weights of the face's nodes,
  // and the spring's stiffness where it is within reach of contact (else 0).
  struct Candidate {
    Index slave = 0, face = 0;
    Vec3 force = Vec3::Zero();
    std::array<double, 4> N{};
    double stiffness = 0;
    double face_inverse_mass = 0; // Σ N_a²/m_a of the face's nodes, 1/kg
  };

  int pair_index(int a, int b) const { return pair_of_[a * bodies_ + b]; }
  // Whether row i may press on a face: a particle of a body paired with a hexahedral body, or a
  // node on the live surface of such a body.
  bool slave(const Particles& p, Index i) const;
  void build_faces(const Particles& p, const HexElements& elements);
  // The faces' corners' rows now (a distributed run's rank holds the rows near its own only,
  // laid anew with each neighbour list; a face far from them has corners it does not hold).
  void locate_faces(const Particles& p);
  void build_candidates(Particles& p, const NeighbourList& list);
  // The slaves this rank evaluates, and the rows they read added to the halo (collective).
  void share(const Particles& p, const ContactRanks& ranks);
  ContactTotals spheres(Particles& p, const NeighbourList& list, double dt,
                        const ContactRanks* ranks) const;
  void update_normals(const Particles& p);
  ContactTotals segments(Particles& p, double dt, const ContactRanks* ranks);
  ContactTotals gather(Particles& p, const ContactRanks* ranks) const;
  Index eroded_count(const HexElements& elements) const;

  int bodies_ = 0;
  std::vector<std::string> names_; // per body, for messages
  std::vector<int> pair_of_;       // bodies × bodies → index into pairs_, −1 if none
  std::vector<Pair> pairs_;
  std::vector<char> in_pair_;             // per body: in a surface pair
  std::vector<char> sphere_partner_;      // per body: its particles meet another body's particles
  std::vector<char> face_partner_;        // per body: paired with a hexahedral body
  std::vector<int> fem_bodies_;           // hexahedral bodies in a surface pair: they have faces
  bool erodes_ = false;                   // some of them erode
  std::vector<std::vector<Quad>> cut_;    // per body: its symmetry faces, which are not surface
  std::vector<Index> background_of_node_; // node → background particle, −1 if none
  std::vector<Vec3> x0_;                  // per background particle: its reference position, m

  std::vector<Face> faces_;
  // Per background particle: its tributary area on live surface faces (m²), its area-weighted
  // V0/A0 under those faces (m) and the outward normal of its surface faces now.
  std::vector<double> area_;
  std::vector<double> thickness_;
  std::vector<Vec3> normal_;
  Index eroded_seen_ = -1;         // eroded elements of fem_bodies_ when faces_ was built
  long long built_for_ = -1;       // the neighbour build the candidates come from
  long long candidate_builds_ = 0; // candidate lists built so far
  // A distributed run: the candidate list and the share of rows the reads were added for, and
  // per slave whether this rank evaluates it.
  std::pair<long long, long long> shared_for_{-1, -1};
  std::vector<unsigned char> evaluated_;
  std::vector<Candidate> candidates_;          // grouped by slave, faces ascending
  std::vector<Index> slave_rows_;              // the rows with candidates, ascending
  std::vector<Index> slave_offsets_;           // per slave, into candidates_
  std::vector<Index> slave_of_row_;            // row → index into slave_rows_, −1 if none
  std::vector<Index> master_offsets_;          // per background row, into master_entries_
  std::vector<Index> master_entries_;          // candidate · 4 + corner, ascending
  std::vector<std::pair<Index, Index>> found_; // scratch: (slave row, face)
  std::vector<Index> cursor_;                  // scratch: write positions in master_entries_
};

} // namespace sphfem
