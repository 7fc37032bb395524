#include "solver/fem/hex_update.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/fem/hex8.hpp"
#include "solver/material/material_point.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphfem {

namespace {

HexPoints gather(const std::vector<Vec3>& field, const Hex& nodes) {
  HexPoints out;
  for (int I = 0; I < 8; ++I)
    out[I] = field[nodes[I]];
  return out;
}

// Bulk viscosity q = ρ L (C0 L ε̇² − C1 c ε̇) in compression (ε̇ = tr D < 0), else 0.
double bulk_viscosity(double rho, double length, double c, double trace_D, const FemSpec& fem) {
  if (trace_D >= 0)
    return 0;
  return rho * length *
         (fem.bulk_viscosity_quadratic * length * trace_D * trace_D -
          fem.bulk_viscosity_linear * c * trace_D);
}

// The hourglass resistance's stiffness (or damping) matrix over its coefficient is
// Σ_α γ_α γ_αᵀ; its non-zero eigenvalues are those of the 4 × 4 Gram matrix γ_α·γ_β. A
// parallelepiped's modes are orthogonal with |γ_α|² = 8; on a crushed, twisted element the γ_α
// grow (γ_α = Γ_α − (h_α·b_I)/V) and couple: on the struck face of elastic bars meeting at
// 6000 m/s, largest |γ_α|² 81, largest eigenvalue 156 (tests/fem/hex8_test.cpp).
using HourglassGram = Eigen::Matrix4d;

HourglassGram hourglass_gram(const std::array<std::array<double, 8>, 4>& gamma) {
  HourglassGram gram;
  for (int a = 0; a < 4; ++a)
    for (int b = a; b < 4; ++b) {
      double dot = 0;
      for (int I = 0; I < 8; ++I)
        dot += gamma[a][I] * gamma[b][I];
      gram(a, b) = gram(b, a) = dot;
    }
  return gram;
}

// Gershgorin's bound on the largest eigenvalue: cheap, and exact for a parallelepiped.
double gershgorin_bound(const HourglassGram& gram) {
  return gram.cwiseAbs().rowwise().sum().maxCoeff();
}

double largest_eigenvalue(const HourglassGram& gram) {
  return Eigen::SelfAdjointEigenSolver<HourglassGram>(gram, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .maxCoeff();
}

// Removes a failed element of an eroding material: no stress and no force from now on.
void erode(HexElements& e, Index k) {
  const Index s = e.slot(k);
  e.eroded_e[k] = 1;
  e.S_e[s].setZero();
  e.p_e[s] = e.q_e[s] = 0;
  e.f_e[s].fill(Vec3::Zero());
  e.hg_e[s].fill(Vec3::Zero());
}

// The element loop. `General`: some material has an EOS, a strength or erosion; without, the
// loop is the linear elastic one and pays for none of them.
template <bool General>
double update_elements(const HexStepInput& in, const std::vector<Material>& materials,
                       const FemSpec& fem, HexElements& e) {
  const Index n = e.size();
  const IndexRange range = IndexRange::of(in.only, n);
  const bool stiffness = fem.hourglass_form == HourglassForm::Stiffness;
  const double dt = in.dt;
  double dt_min = std::numeric_limits<double>::infinity();
  Index first_inverted = n;

#pragma omp parallel for schedule(static, interleave_chunk)                                        \
    reduction(min                                                                                  \
              : dt_min, first_inverted) if (range.count > parallel_min_items / 16)
  for (Index j = 0; j < range.count; ++j) {
    const Index k = range[j], s = e.slot(k);
    if (General && e.eroded_e[k])
      continue;
    const Hex& nodes = e.nodes_e[k];
    const Material& mat = materials[e.material_e[k]];
    const HexPoints x1 = gather(in.x_new, nodes);
    const HexPoints v = gather(in.v_half, nodes);
    const Hex8Gradient g = hex8_gradient(x1);
    if (!(g.volume > 0)) {
      first_inverted = std::min(first_inverted, k);
      continue;
    }
    const double rho = e.mass_e[k] / g.volume;
    const double energy = General && mat.eos ? e.e_int_e[s] / e.V0_e[k] : 0.0; // E, J/m³
    const double c =
        General ? mat.sound_speed(rho, energy) : std::sqrt(mat.elastic.p_wave_modulus() / rho);
    const double length = hex8_characteristic_length(x1, g.volume);
    double trace_D = 0;

    if (dt > 0) {
      HexPoints xm;
      for (int I = 0; I < 8; ++I)
        xm[I] = x1[I] - 0.5 * dt * v[I];
      const Hex8Gradient gm = hex8_gradient(xm);
      const Mat3 L = hex8_velocity_gradient(gm, v);
      const Mat3 D = 0.5 * (L + L.transpose());
      const Mat3 W = 0.5 * (L - L.transpose());
      trace_D = D.trace();
      const Mat3 sigma_old = e.sigma(s);
      if constexpr (General) {
        // Pressure: the EOS at the new density, else the elastic rate form −K tr D.
        double pressure =
            mat.eos ? mat.pressure(rho, energy) : e.p_e[s] - mat.elastic.bulk * trace_D * dt;
        if (mat.inelastic())
          update_point(mat, D, W, dt, rho, pressure, e.S_e[s], e.point_e[s],
                       mat.regularised() ? std::cbrt(e.V0_e[k]) : 0.0);
        else
          elastic_deviator_update(mat.elastic, D, W, dt, e.S_e[s]);
        e.p_e[s] = pressure;
      } else {
        elastic_update(mat.elastic, D, W, dt, e.S_e[s], e.p_e[s]);
      }
      e.q_e[s] = bulk_viscosity(rho, length, c, trace_D, fem);
      const Mat3 sigma_mid = 0.5 * (sigma_old + e.sigma(s));
      e.de_int_e[s] = dt * gm.volume * sigma_mid.cwiseProduct(D).sum();
      e.e_int_e[s] += e.de_int_e[s];
    }
    e.V_e[s] = g.volume;

    // Internal force on node I: −σ b_I; plus hourglass resistance on the γ modes.
    const Mat3 sigma = e.sigma(s);
    const auto gamma = hex8_hourglass_shape(x1, g);
    std::array<Vec3, 4> mode;
    for (int a = 0; a < 4; ++a) {
      mode[a].setZero();
      for (int I = 0; I < 8; ++I)
        mode[a] += gamma[a][I] * v[I];
    }
    // The mode forces of the last update acted over this step: their work, with the mode
    // velocity averaged over the step, is the hourglass energy (exact leap-frog accounting).
    auto& resist = e.hg_e[s];
    double hourglass_work = 0;
    for (int a = 0; a < 4; ++a)
      hourglass_work += resist[a].dot(0.5 * (e.hg_mode_e[s][a] + mode[a]));
    e.e_hg_e[s] += dt * hourglass_work;
    if (General && mat.erosion && e.point_e[s].failed) {
      erode(e, k);
      continue;
    }
    const double Q = trace_D < 0 ? fem.bulk_viscosity_linear * c +
                                       fem.bulk_viscosity_quadratic * length * std::abs(trace_D)
                                 : 0.0;
    double step = length / (Q + std::sqrt(Q * Q + c * c));
    if (fem.hourglass_coefficient > 0) {
      // The resistance on nodes of mass m ≥ m_e/8 with λ the Gram matrix's largest eigenvalue:
      // a spring k_hg λ, stable for Δt < 2√(m/(k_hg λ)), or explicit damping c_hg λ, stable
      // for Δt < 2m/(c_hg λ). Where Gershgorin's bound on λ would not bind, λ is not needed.
      const double node_mass = e.mass_e[k] / 8.0;
      double coefficient; // k_hg (N/m) or c_hg (N s/m)
      if (stiffness) {
        coefficient =
            fem.hourglass_coefficient * mat.elastic.p_wave_modulus() * std::cbrt(g.volume) / 4.0;
        for (int a = 0; a < 4; ++a)
          resist[a] += dt * coefficient * mode[a];
      } else {
        const double edge = std::cbrt(g.volume);
        coefficient = fem.hourglass_coefficient * rho * c * edge * edge / 4.0;
        for (int a = 0; a < 4; ++a)
          resist[a] = coefficient * mode[a];
      }
      const auto hourglass_step = [&](double lambda) {
        return stiffness ? 2.0 * std::sqrt(node_mass / (coefficient * lambda))
                         : 2.0 * node_mass / (coefficient * lambda);
      };
      const HourglassGram gram = hourglass_gram(gamma);
      if (hourglass_step(gershgorin_bound(gram)) < step)
        step = std::min(step, hourglass_step(largest_eigenvalue(gram)));
    }
    e.hg_mode_e[s] = mode;
    for (int I = 0; I < 8; ++I) {
      Vec3 f_hg = Vec3::Zero();
      for (int a = 0; a < 4; ++a)
        f_hg -= gamma[a][I] * resist[a];
      e.f_e[s][I] = -(sigma * g.b[I]) + f_hg;
    }
    dt_min = std::min(dt_min, step);
  }
  SPHFEM_CHECK(first_inverted == n, "element ", first_inverted,
               " inverted (non-positive volume): the mesh tangled; reduce time.cfl or refine");
  return dt_min;
}

} // namespace

double update_hex_elements(const HexStepInput& in, const std::vector<Material>& materials,
                           const FemSpec& fem, HexElements& e) {
  const bool general = std::ranges::any_of(
      materials, [](const Material& m) { return m.eos || m.inelastic() || m.erosion; });
  return general ? update_elements<true>(in, materials, fem, e)
                 : update_elements<false>(in, materials, fem, e);
}

} // namespace sphfem
