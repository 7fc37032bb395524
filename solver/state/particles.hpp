// SPH particles as a struct of arrays (STYLE.md B): kinematics, material state and the
// per-step rates, plus for_each_field so resizing, exchanges and checkpoints never forget a
// field.
#pragma once

#include "solver/core/types.hpp"
#include "solver/material/material_point.hpp"

#include <cstdint>
#include <vector>

namespace sphfem {

// Particle kill (METHOD.md §6): a failed particle stays in its neighbours' sums while
// compressed (p > 0) and drops out of them while in tension; it keeps its mass and momentum.
enum class Kill : std::uint8_t { None, Compressed, Tension };

// The arrays hold the `real` SPH particles first, then the `background` particles of FE nodes
// (METHOD.md §4.1): copies of nodal state that appear in the real particles' sums (attachment,
// contact) but are not integrated here; then the mirror images of real particles across
// symmetry planes, which only appear in the real particles' sums. size() counts the real
// particles, rows() real and background (the entities that gather sums), total() all.
struct Particles {
  Index real = 0;
  Index model_real = 0; // the model's real particles (a distributed run's rank holds some of them)
  Index background = 0;
  Index model_background = 0; // the model's background particles (likewise)
  // A distributed run's rank holds some background particles only: per background row here
  // (row − real) its background particle, and per background particle its row here (−1: not
  // held). Both empty: every one, in order (background particle k in row real + k).
  std::vector<Index> background_of_row;
  std::vector<Index> row_of_background;
  Index mirrored_real = 0; // mirror images of real particles (the first ones after rows())
  bool inelastic = false;  // some particle's material carries a plastic/damage history
  Index excluded = 0;      // real particles killed and in tension (out of all sums)

  // State.
  std::vector<Vec3> x0_p;     // reference position, m
  std::vector<Vec3> x_p;      // position xⁿ, m
  std::vector<Vec3> v_p;      // velocity v^{n−½} (after a step v^{n+½}), m/s
  std::vector<double> m_p;    // mass, kg
  std::vector<double> rho0_p; // reference density, kg/m³
  std::vector<double> rho_p;  // density, kg/m³
  std::vector<double> h_p;    // smoothing length, m
  std::vector<double> h0_p;   // initial smoothing length, m
  std::vector<double> dp_p;   // initial lattice spacing Δp (artificial stress), m
  std::vector<Mat3> S_p;      // deviatoric stress, Pa
  std::vector<double> p_p;    // pressure, Pa
  std::vector<double> e_p;    // internal energy, J (stress work and viscous heating)
  std::vector<double> de_p;   // stress work of the last step, J (energy at the half step)
  std::vector<int> body_p;
  std::vector<int> group_p; // bodies glued by attachment share a group; sums run within one
  std::vector<int> material_p;
  // Index in model.h5: the row's own, but in a checkpoint written before 2026-12-07 (rows were
  // renumbered by cell then).
  std::vector<Index> id_p;
  std::vector<MaterialPoint> point_p; // plastic strain, damage, temperature (inelastic materials)
  std::vector<Kill> kill_p;           // particle kill state
  // Surface contact (coupling/surface_contact.hpp), per slave: its signed distance from the
  // other body's surface at the last evaluation (NaN: none yet), and the overlap it ignores
  // after that surface changed under it (coupling/ignored_overlap.hpp), m.
  std::vector<double> contact_s_p;
  std::vector<double> ignored_overlap_p;
  // Rates and scratch of the current step.
  std::vector<Vec3> f_p;      // force on the particle, N
  std::vector<Mat3> L_p;      // velocity gradient, 1/s
  std::vector<Mat3> C_p;      // gradient correction C = M⁻¹ (identity when off), 1
  std::vector<Mat3> G_p;      // Σ_j m_j v_ji ⊗ ∇W C = ρ L (stress power), kg/(m³ s)
  std::vector<double> drho_p; // dρ/dt, kg/m³/s
  std::vector<Vec3> xsph_p;   // XSPH velocity correction, m/s
  std::vector<Vec3> u_p;      // drift velocity of the last step, v + XSPH, m/s
  std::vector<Vec3> xm_p;     // mid-step position x^{n+½} = x^{n+1} − ½Δt u (kinematics), m
  std::vector<double> heat_p; // heating power of artificial viscosity and stress, W
  std::vector<Vec3> vn_p;     // velocity predicted at the next kick's time, for heat_p, m/s
  std::vector<Mat3> A_p;      // σ Cᵀ/ρ² for the momentum pair term, Pa m⁶/kg²
  std::vector<double> c_p;    // sound speed √((K + 4G/3)/ρ), m/s
  std::vector<double> shear_p; // Balsara factor |∇·v|/(|∇·v| + |∇×v|): 1 in compression, 0 in shear
  std::vector<Mat3> R_p;         // artificial stress R_i (METHOD.md §2), Pa m⁶/kg²
  std::vector<int> neighbours_p; // neighbour count (within 2h), for output
  std::vector<Vec3> fc_p;        // contact force on the particle (part of f_p), N
  std::vector<Vec3> fm_p;        // force from mirror images: the symmetry planes' reaction, N
  std::vector<double> phi_p;     // kernel-contact energy of the row's pairs (half of each), J

  // What a row starts a run with besides the fresh state start_row() gives every row.
  struct RowStart {
    Vec3 x, v;            // position (also the reference position), velocity
    double m, rho, h, dp; // mass, density (also the reference), smoothing length, spacing
    int body, group;      // the body (also the material entry: one per body) and its group
    Index id;             // index in model.h5, −1 for a row that stands for something else
    MaterialPoint point;  // the material's initial point
  };
  // Row i at the start of a run: as `s` says, unstressed, uncorrected, no force on it.
  void start_row(Index i, const RowStart& s) {
    x0_p[i] = x_p[i] = s.x;
    v_p[i] = s.v;
    m_p[i] = s.m;
    rho0_p[i] = rho_p[i] = s.rho;
    h0_p[i] = h_p[i] = s.h;
    dp_p[i] = s.dp;
    S_p[i].setZero();
    p_p[i] = e_p[i] = de_p[i] = 0;
    body_p[i] = material_p[i] = s.body;
    group_p[i] = s.group;
    point_p[i] = s.point;
    kill_p[i] = Kill::None;
    id_p[i] = s.id;
    R_p[i].setZero();
    shear_p[i] = 1;       // a background row's pairs: the real particle's factor decides
    C_p[i].setIdentity(); // corrected later for real particles; background rows never are
    A_p[i].setZero();
    u_p[i].setZero();
    f_p[i].setZero();
    fc_p[i].setZero();
    fm_p[i].setZero();
    phi_p[i] = 0;
  }

  Index background_row(Index k) const {
    return row_of_background.empty() ? real + k : row_of_background[k];
  }
  Index background_particle(Index row) const {
    return background_of_row.empty() ? row - real : background_of_row[row - real];
  }

  Index size() const { return real; }
  Index rows() const { return real + background; }
  // A real particle or the mirror image of one: what background particles pair with.
  bool real_like(Index j) const { return j < real || (j >= rows() && j < rows() + mirrored_real); }
  // Killed and in tension: out of every other particle's sums.
  bool out_of_sums(Index j) const { return kill_p[j] == Kill::Tension; }
  Index total() const { return static_cast<Index>(x_p.size()); }

  // Visits every per-particle array with its name (resize, exchange, checkpoint).
  template <class Visit> void for_each_field(Visit visit) {
    visit("x0_p", x0_p);
    visit("x_p", x_p);
    visit("v_p", v_p);
    visit("m_p", m_p);
    visit("rho0_p", rho0_p);
    visit("rho_p", rho_p);
    visit("h_p", h_p);
    visit("h0_p", h0_p);
    visit("dp_p", dp_p);
    visit("S_p", S_p);
    visit("p_p", p_p);
    visit("e_p", e_p);
    visit("body_p", body_p);
    visit("group_p", group_p);
    visit("material_p", material_p);
    visit("id_p", id_p);
    visit("point_p", point_p);
    visit("kill_p", kill_p);
    visit("contact_s_p", contact_s_p);
    visit("ignored_overlap_p", ignored_overlap_p);
    visit("f_p", f_p);
    visit("L_p", L_p);
    visit("C_p", C_p);
    visit("drho_p", drho_p);
    visit("xsph_p", xsph_p);
    visit("u_p", u_p);
    visit("xm_p", xm_p);
    visit("G_p", G_p);
    visit("de_p", de_p);
    visit("heat_p", heat_p);
    visit("vn_p", vn_p);
    visit("A_p", A_p);
    visit("c_p", c_p);
    visit("shear_p", shear_p);
    visit("R_p", R_p);
    visit("neighbours_p", neighbours_p);
    visit("fc_p", fc_p);
    visit("fm_p", fm_p);
    visit("phi_p", phi_p);
  }

  // What a distributed run's neighbour-list rebuild reads of the rows near a rank's own, which
  // their owners send (parallel/particle_share.hpp): where the rows are and how far they reach.
  // The rows a rank reads after the rebuild are then refreshed whole.
  template <class Visit> void for_each_listed_field(Visit visit) {
    visit("x_p", x_p);
    visit("h_p", h_p);
  }

  // What a distributed run's halo refresh carries (parallel/particle_share.hpp), in two parts
  // that together hold every field another rank reads; each carries what the owners wrote since
  // the other. Before the kinematics: what the forces, contact, kick, ties, boundary conditions,
  // drift and the background fill (x, v, u, m, ρ, p, S, f of background rows) wrote.
  template <class Visit> void for_each_moved_field(Visit visit) {
    visit("x_p", x_p);
    visit("v_p", v_p);
    visit("u_p", u_p);
    visit("m_p", m_p);
    visit("rho_p", rho_p);
    visit("S_p", S_p);
    visit("p_p", p_p);
    visit("e_p", e_p);
    visit("f_p", f_p);
    visit("fc_p", fc_p);
    visit("fm_p", fm_p);
    visit("heat_p", heat_p);
    visit("phi_p", phi_p);
    visit("contact_s_p", contact_s_p);
    visit("ignored_overlap_p", ignored_overlap_p);
  }
  // Before the forces: what the kinematics and the material update wrote and the forces, the
  // mirror images or the contact read (L, G, dρ/dt, the XSPH correction and the neighbour count
  // stay with the owner).
  template <class Visit> void for_each_updated_field(Visit visit) {
    visit("rho_p", rho_p);
    visit("h_p", h_p);
    visit("S_p", S_p);
    visit("p_p", p_p);
    visit("e_p", e_p);
    visit("de_p", de_p);
    visit("C_p", C_p);
    visit("R_p", R_p);
    visit("shear_p", shear_p);
    visit("point_p", point_p);
    visit("kill_p", kill_p);
  }
};

} // namespace sphfem
