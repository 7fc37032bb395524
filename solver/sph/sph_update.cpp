#include "solver/sph/sph_update.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/material/jaumann.hpp"
#include "solver/material/material_point.hpp"
#include "solver/sph/kernel.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphfem {

namespace {

Mat3 total_stress(const Particles& p, Index i) {
  return p.S_p[i] - p.p_p[i] * Mat3::Identity();
}

// R_i = −ε Σ_k max(σ'_k, 0)/ρ² e_k e_kᵀ over the principal stresses σ'_k (Gray et al. 2001).
Mat3 artificial_stress(const Mat3& sigma, double rho, double epsilon) {
  Eigen::SelfAdjointEigenSolver<Mat3> eigen;
  eigen.computeDirect(sigma);
  Mat3 R = Mat3::Zero();
  for (int k = 0; k < 3; ++k) {
    const double s = eigen.eigenvalues()[k];
    if (s > 0) {
      const Vec3 e = eigen.eigenvectors().col(k);
      R -= (epsilon * s / (rho * rho)) * (e * e.transpose());
    }
  }
  return R;
}

// x^n by repeated squaring: std::pow took a fifth of the force loop for the usual n = 4.
double power(double x, int n) {
  double result = 1.0;
  for (; n > 0; n >>= 1, x *= x)
    if (n & 1)
      result *= x;
  return result;
}

// Internal energy per initial volume (J/m³), the EOS's E: e V0⁻¹ with V0 = m/ρ0, where the
// material has an EOS. Background and mirror rows carry no energy of their own.
double energy_density(const Particles& p, const Material& m, Index i) {
  return m.eos && i < p.size() ? p.e_p[i] * p.rho0_p[i] / p.m_p[i] : 0.0;
}

} // namespace

namespace {

// Background particles: the gradient correction C = M⁻¹ from their neighbours of the same
// group (real and background: the FE continuum around them), so that their pair terms
// σ Cᵀ/ρ² match those of the real particles they stand beside (in a bar only a few particles
// wide, every particle is near a lateral surface and C ≠ I); and their half of the stress
// power of their pairs with real particles, m_b (σ_b Cᵀ/ρ_b²) : Σ_j m_j v_jb ⊗ ∇W, σ Cᵀ/ρ²
// taken half-way between the last force evaluation (A_p) and the FE stress just copied in:
// the energy the coupling stores, which the FE elements do not see. With it, energy is
// balanced across the interface as inside SPH. And their artificial stress, from the FE stress.
void background_kinematics(Particles& p, const NeighbourList& list, const SphSpec& spec, double dt,
                           IndexRange rows_of) {
  const bool excluded = p.excluded > 0;
#pragma omp parallel for schedule(static,                                                          \
                                  interleave_chunk) if (rows_of.count > parallel_min_items / 16)
  for (Index k = 0; k < rows_of.count; ++k) {
    const Index b = rows_of[k];
    const Vec3 xb = p.xm_p[b], vb = p.v_p[b];
    Mat3 G = Mat3::Zero(), M = Mat3::Zero();
    for (Index j : list.of(b)) {
      if (p.group_p[j] != p.group_p[b] || (excluded && p.out_of_sums(j)))
        continue;
      const Vec3 x_bj = xb - p.xm_p[j];
      const double r2 = x_bj.squaredNorm(), h_bj = 0.5 * (p.h_p[b] + p.h_p[j]);
      if (!within_support(r2, h_bj))
        continue;
      const Vec3 grad = pair_kernel(r2, h_bj).grad_scale * x_bj;
      M -= p.m_p[j] * x_bj * grad.transpose();
      if (p.real_like(j))
        G += p.m_p[j] * (p.v_p[j] - vb) * grad.transpose();
    }
    M *= 1.0 / p.rho_p[b];
    p.C_p[b] = gradient_correction(M, spec.gradient_correction);
    const Mat3 A_new =
        total_stress(p, b) * p.C_p[b].transpose() * (1.0 / (p.rho_p[b] * p.rho_p[b]));
    p.de_p[b] = dt * p.m_p[b] * (0.5 * (p.A_p[b] + A_new)).cwiseProduct(G).sum();
    p.e_p[b] += p.de_p[b];
    if (spec.artificial_stress)
      p.R_p[b] = artificial_stress(total_stress(p, b), p.rho_p[b], spec.epsilon);
  }
}

} // namespace

namespace {

// The kinematics of real particle i. With `Kill`, some particles are killed in tension: such a
// particle is out of the others' sums and they of its, but its own density still follows all
// its neighbours, so that it sees when it is compressed again. Without, the loop has no test.
template <bool Kill>
void particle_kinematics(Particles& p, const NeighbourList& list, const SphSpec& spec, Index i) {
  // Mid-step geometry x^{n+½} = x^{n+1} − ½Δt u (u the drift velocity, xm_p): a rigid rotation
  // then has an exactly skew velocity gradient, as for the hexahedra.
  const Vec3 xi = p.xm_p[i], vi = p.v_p[i];
  const int group = p.group_p[i];
  [[maybe_unused]] const bool out = Kill && p.out_of_sums(i);
  Mat3 M = Mat3::Zero(), G = Mat3::Zero();
  Vec3 xsph = Vec3::Zero();
  double drho = 0;
  int count = 0;
  for (Index j : list.of(i)) {
    if (p.group_p[j] != group)
      continue;
    const Vec3 x_ij = xi - p.xm_p[j];
    const double r2 = x_ij.squaredNorm(), h_ij = 0.5 * (p.h_p[i] + p.h_p[j]);
    if (!within_support(r2, h_ij))
      continue;
    const PairKernel k = pair_kernel(r2, h_ij);
    const Vec3 grad = k.grad_scale * x_ij;
    const Vec3 v_ji = p.v_p[j] - vi;
    if constexpr (Kill) {
      if (out || p.out_of_sums(j)) {
        if (out)
          drho -= p.m_p[j] * v_ji.dot(grad);
        continue;
      }
    }
    ++count;
    G += p.m_p[j] * v_ji * grad.transpose();
    M -= p.m_p[j] * x_ij * grad.transpose();
    drho -= p.m_p[j] * v_ji.dot(grad);
    if (spec.xsph)
      xsph += (2.0 * p.m_p[j] / (p.rho_p[i] + p.rho_p[j]) * k.W) * v_ji;
  }
  // Gradient correction (Randles & Libersky; Bonet & Lok 1999): with C = M⁻¹,
  // M = −(1/ρ_i) Σ_j m_j x_ij ⊗ ∇W, the gradient G C/ρ_i of every linear field is exact, also
  // at free surfaces where the kernel support is cut. The momentum pair term uses the same C
  // (A = σ Cᵀ/ρ², the transpose of this gradient), so stress power and force work agree pair
  // by pair, and a uniform stress loads only the surface.
  M *= 1.0 / p.rho_p[i];
  const Mat3 C = gradient_correction(M, spec.gradient_correction);
  p.C_p[i] = C;
  p.G_p[i] = G * C;
  p.L_p[i] = p.G_p[i] * (1.0 / p.rho_p[i]);
  p.drho_p[i] = drho;
  p.xsph_p[i] = spec.xsph_epsilon * xsph;
  p.neighbours_p[i] = count;
}

// f(i) for the visible rows and mirror images (all if null), in parallel.
template <class F> void for_visible(const Particles& p, const std::vector<Index>* visible, F f) {
  const IndexRange rows = IndexRange::of(visible, p.total());
#pragma omp parallel for schedule(static) if (rows.count > parallel_min_items)
  for (Index k = 0; k < rows.count; ++k)
    f(rows[k]);
}

} // namespace

void sph_kinematics(Particles& p, const NeighbourList& list, const SphSpec& spec, double dt,
                    const std::vector<Index>* only, const std::vector<Index>* visible) {
  const bool kill = p.excluded > 0;
  for_visible(p, visible, [&](Index i) { p.xm_p[i] = p.x_p[i] - 0.5 * dt * p.u_p[i]; });
  const IndexRange real = IndexRange::of(only, 0, p.size());
#pragma omp parallel for schedule(static,                                                          \
                                  interleave_chunk) if (real.count > parallel_min_items / 16)
  for (Index k = 0; k < real.count; ++k) {
    if (kill)
      particle_kinematics<true>(p, list, spec, real[k]);
    else
      particle_kinematics<false>(p, list, spec, real[k]);
  }
  background_kinematics(p, list, spec, dt, IndexRange::of(only, p.size(), p.rows()));
}

void sph_material_update(Particles& p, const std::vector<Material>& materials, const SphSpec& spec,
                         double dt, const std::vector<Index>* only) {
  const Index n = p.size();
  const IndexRange real = IndexRange::of(only, 0, n);
  Index first_bad = n, excluded = 0;
#pragma omp parallel for schedule(static, interleave_chunk) reduction(min : first_bad) reduction(+ : excluded) if (real.count > parallel_min_items / 4)
  for (Index k = 0; k < real.count; ++k) {
    const Index i = real[k];
    const Material& mat = materials[p.material_p[i]];
    const double rho_old = p.rho_p[i];
    double rho = rho_old + dt * p.drho_p[i];
    // A particle killed in tension is the face of a crack: it does not expand with the parting
    // pieces (its density would fall without bound, and its h — and with the largest h every
    // particle's neighbour reach — grow without bound); it only sees compression, which brings
    // it back into the sums when the crack closes.
    if (p.out_of_sums(i))
      rho = std::max(rho, rho_old);
    if (!(rho > 0)) {
      first_bad = std::min(first_bad, i);
      continue;
    }
    p.rho_p[i] = rho;
    if (spec.variable_h)
      p.h_p[i] = p.h0_p[i] * std::cbrt(p.rho0_p[i] / rho);
    const Mat3& L = p.L_p[i];
    const Mat3 D = 0.5 * (L + L.transpose()), W = 0.5 * (L - L.transpose());
    if (spec.balsara) {
      // Balsara (1995): |∇·v| / (|∇·v| + |∇×v| + ε c/h), ε = 1e-4 against 0/0 at rest.
      const double divergence = std::abs(L.trace());
      const double curl = Vec3(L(2, 1) - L(1, 2), L(0, 2) - L(2, 0), L(1, 0) - L(0, 1)).norm();
      p.shear_p[i] = divergence / (divergence + curl + 1e-4 * mat.sound_speed(rho, 0) / p.h_p[i]);
    }
    const Mat3 sigma_old = total_stress(p, i);
    double pressure = mat.pressure(rho, energy_density(p, mat, i));
    if (mat.inelastic()) {
      update_point(mat, D, W, dt, rho, pressure, p.S_p[i], p.point_p[i], 2.0 * p.h0_p[i]);
      if (p.point_p[i].failed) {
        p.kill_p[i] = pressure > 0 ? Kill::Compressed : Kill::Tension;
        excluded += p.kill_p[i] == Kill::Tension;
      }
    } else {
      elastic_deviator_update(mat.elastic, D, W, dt, p.S_p[i]);
    }
    p.p_p[i] = pressure;
    // Stress work in the form that matches the symmetric momentum equation pair by pair,
    // m_i (σ/ρ²) : Σ_j m_j v_ji ⊗ ∇W C = m_i σ : L / ρ, so the total energy is conserved.
    const Mat3 sigma_mid = 0.5 * (sigma_old + total_stress(p, i));
    const double rho_mid = 0.5 * (rho_old + rho);
    p.de_p[i] = dt * p.m_p[i] / (rho_mid * rho_mid) * sigma_mid.cwiseProduct(p.G_p[i]).sum();
    p.e_p[i] += p.de_p[i];
    if (spec.artificial_stress)
      p.R_p[i] = artificial_stress(total_stress(p, i), rho, spec.epsilon);
  }
  SPHFEM_CHECK(first_bad == n, "particle ", first_bad < n ? p.id_p[first_bad] : -1,
               " reached a non-positive density: the particle set is being crushed; the run is "
               "unstable (reduce sph.cfl)");
  p.excluded = excluded;
}

double sph_forces(Particles& p, const NeighbourList& list, const std::vector<Material>& materials,
                  const SphSpec& spec, double dt, const std::vector<Index>* only,
                  const std::vector<Index>* visible) {
  const Index n = p.size(), rows = p.rows();
  const IndexRange rows_of = IndexRange::of(only, 0, rows);
  const bool excluded = p.excluded > 0;
  const int exponent = static_cast<int>(std::lround(spec.stress_exponent));
  // σ Cᵀ/ρ² and the sound speed once per particle, not once per pair.
  for_visible(p, visible, [&](Index i) {
    p.A_p[i] = total_stress(p, i) * p.C_p[i].transpose() * (1.0 / (p.rho_p[i] * p.rho_p[i]));
    const Material& mat = materials[p.material_p[i]];
    p.c_p[i] = mat.sound_speed(p.rho_p[i], energy_density(p, mat, i));
    p.vn_p[i] = p.v_p[i] + (0.5 * dt / p.m_p[i]) * p.f_p[i];
  });
  // Real particles gather from every neighbour of their group (mirror images included);
  // background particles only from real ones (and their images), so each gets exactly minus
  // what it exerts (returned to its FE node). Mirror images gather nothing.
  double dt_min = std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(static, interleave_chunk)                                        \
    reduction(min                                                                                  \
              : dt_min) if (rows_of.count > parallel_min_items / 16)
  for (Index k = 0; k < rows_of.count; ++k) {
    const Index i = rows_of[k];
    const Vec3 xi = p.x_p[i], vi = p.v_p[i], vni = p.vn_p[i];
    const int group = p.group_p[i];
    const bool real = i < n;
    const double rho_i = p.rho_p[i];
    const double c_i = p.c_p[i];
    const Mat3& A_i = p.A_p[i];
    Vec3 f = Vec3::Zero(), f_mirror = Vec3::Zero();
    double heat = 0;
    for (Index j : list.of(i)) {
      if (p.group_p[j] != group || !(real || p.real_like(j)) ||
          (excluded && (p.out_of_sums(i) || p.out_of_sums(j))))
        continue;
      const Vec3 x_ij = xi - p.x_p[j];
      const double r2 = x_ij.squaredNorm(), h_ij = 0.5 * (p.h_p[i] + p.h_p[j]);
      if (!within_support(r2, h_ij))
        continue;
      const double rho_j = p.rho_p[j];
      const PairKernel k = pair_kernel(r2, h_ij);
      const Vec3 grad = k.grad_scale * x_ij;
      const Vec3 v_ij = vi - p.v_p[j], vn_ij = vni - p.vn_p[j];
      const double mm = p.m_p[i] * p.m_p[j];
      const Mat3 pair = A_i + p.A_p[j];
      Vec3 f_ij = mm * (pair * grad);
      // R = 0 where no principal stress is tensile (trace R = −ε Σ max(σ'_k, 0)/ρ², zero only
      // then): the term, its kernel ratio and its power are skipped for such pairs.
      if (spec.artificial_stress && p.R_p[i].trace() + p.R_p[j].trace() < 0) {
        // W(r, h)/W(Δp, h) = w(q)/w(Δp/h): the normalisations cancel.
        const double dp = 0.5 * (p.dp_p[i] + p.dp_p[j]);
        const double fij = power(kernel_shape(k.q) / kernel_shape(dp * k.inv_h), exponent);
        const Vec3 f_R = (mm * fij) * ((p.R_p[i] + p.R_p[j]) * grad);
        f_ij += f_R;
        heat -= 0.5 * f_R.dot(vn_ij);
      }
      const double approach = v_ij.dot(x_ij);
      if (spec.artificial_viscosity && approach < 0) {
        const double c_j = p.c_p[j];
        const double mu = h_ij * approach / (r2 + 0.01 * h_ij * h_ij);
        double Pi =
            (-spec.alpha * 0.5 * (c_i + c_j) * mu + spec.beta * mu * mu) / (0.5 * (rho_i + rho_j));
        if (spec.balsara)
          Pi *= 0.5 * (p.shear_p[i] + p.shear_p[j]);
        f_ij -= (mm * Pi) * grad;
        heat += 0.5 * mm * Pi * vn_ij.dot(grad);
      }
      f += f_ij;
      if (j >= rows)
        f_mirror += f_ij;
    }
    p.f_p[i] = f;
    p.fm_p[i] = f_mirror;
    p.heat_p[i] = heat;
    if (i < n)
      dt_min = std::min(dt_min, p.h_p[i] / (c_i + vi.norm()));
  }
  return spec.cfl * dt_min;
}

} // namespace sphfem
