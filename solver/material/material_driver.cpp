// The material-point driver (material_driver.hpp, METHOD.md §5): the strain paths, and the
// lateral-rate solve of uniaxial stress, around the solver's own update_point().
#include "solver/material/material_driver.hpp"

#include "solver/core/error.hpp"
#include "solver/material/material_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphfem {

namespace {

// Everything one increment changes.
struct PointState {
  Mat3 S = Mat3::Zero(); // deviatoric stress, Pa
  double p = 0;          // pressure, Pa
  double rho = 0;        // density, kg/m³
  double E = 0;          // internal energy per initial volume, J/m³
  MaterialPoint point;
  double dp = 0; // plastic strain increment of the last step
};

Mat3 cauchy(const PointState& s) {
  return s.S - s.p * Mat3::Identity();
}

// One increment from `start`, as the solver takes it: density, EOS pressure at the new
// density (energy of the step start), then the point update; the energy last.
PointState advance(const Material& m, const PointState& start, const Mat3& D, const Mat3& W,
                   double dt, double band_width) {
  PointState s = start;
  s.rho = start.rho * std::exp(-D.trace() * dt);
  s.p = m.pressure(s.rho, start.E);
  s.dp = update_point(m, D, W, dt, s.rho, s.p, s.S, s.point, band_width);
  const double power = 0.5 * (cauchy(start) + cauchy(s)).cwiseProduct(D).sum();
  s.E = start.E + power * dt * m.elastic.density / s.rho;
  return s;
}

Mat3 diagonal(double xx, double yy, double zz) {
  return Vec3(xx, yy, zz).asDiagonal();
}

// The increment of uniaxial stress: the lateral rate d that makes σ_yy = S_yy − p vanish.
// σ_yy grows monotonically with d (more lateral stretch, less pressure), so a secant iteration
// kept inside the bracket of the signs found so far (bisection when it leaves it) converges;
// every trial restarts from `start`. `d` holds the guess (the previous increment's rate) and
// returns the solution.
PointState uniaxial_stress_increment(const Material& m, const PointState& start, double rate,
                                     double dt, double band_width, double& d) {
  constexpr int max_trials = 200;
  const auto trial = [&](double lateral, double& residual) {
    PointState s =
        advance(m, start, diagonal(rate, lateral, lateral), Mat3::Zero(), dt, band_width);
    residual = s.S(1, 1) - s.p;
    return s;
  };
  const auto converged = [](const PointState& s, double residual) {
    return std::abs(residual) <= 1e-8 * std::max(std::abs(s.S(0, 0) - s.p), 1.0);
  };
  // Elastic slope dσ_yy/dd ≈ 2K Δt (pressure) + 2G Δt/3 (deviator): the first step's guess.
  double slope = (2.0 * m.elastic.bulk + 2.0 * m.elastic.shear / 3.0) * dt;
  constexpr double inf = std::numeric_limits<double>::infinity();
  double lo = -inf, hi = inf; // rates known to give σ_yy < 0 and > 0
  double f = 0;
  PointState s = trial(d, f);
  for (int k = 0; k < max_trials; ++k) {
    if (converged(s, f))
      return s;
    (f < 0 ? lo : hi) = d;
    double next = d - f / slope;
    if (!(next > lo && next < hi)) // only possible once both bounds are known
      next = 0.5 * (lo + hi);
    double f_next = 0;
    PointState s_next = trial(next, f_next);
    const double secant = (f_next - f) / (next - d);
    if (secant > 0 && std::isfinite(secant))
      slope = secant;
    d = next;
    f = f_next;
    s = s_next;
  }
  SPHFEM_CHECK(converged(s, f), "material driver: the lateral stress of uniaxial stress did not ",
               "vanish at plastic strain ", start.point.plastic_strain, " (σ_yy = ", f, " Pa)");
  return s;
}

DriverRow row_of(const PointState& s, double time, double strain, double rate, double dt) {
  DriverRow r;
  r.time = time;
  r.strain = strain;
  r.strain_rate = rate;
  r.stress = cauchy(s);
  r.von_mises = equivalent_stress(s.S);
  r.pressure = s.p;
  r.plastic_strain = s.point.plastic_strain;
  r.plastic_strain_rate = dt > 0 ? s.dp / dt : 0.0;
  r.damage = s.point.damage;
  r.temperature = s.point.temperature;
  r.density = s.rho;
  r.failed = s.point.failed;
  return r;
}

} // namespace

std::vector<DriverRow> drive_material(const Material& m, const DriverOptions& o) {
  SPHFEM_CHECK(std::isfinite(o.strain_rate) && o.strain_rate != 0,
               "material driver: the strain rate must be a non-zero number, got ", o.strain_rate);
  SPHFEM_CHECK(std::isfinite(o.final_strain) && o.final_strain / o.strain_rate > 0,
               "material driver: the final strain must be non-zero and of the sign of the strain "
               "rate, got ",
               o.final_strain, " at ", o.strain_rate, " 1/s");
  SPHFEM_CHECK(o.increments >= 1, "material driver: at least one increment, got ", o.increments);
  SPHFEM_CHECK(std::isfinite(o.band_width) && o.band_width >= 0,
               "material driver: the band width must be ≥ 0 (m), got ", o.band_width);
  SPHFEM_CHECK(o.band_width == 0 || m.regularised(),
               "material driver: a band width scales only a regularised fracture strain "
               "(damage.regularisation_length); this material has none");
  const double rate = o.strain_rate;
  const double dt = o.final_strain / rate / o.increments;

  PointState s;
  s.rho = m.elastic.density;
  s.point = MaterialPoint::initial(m);
  if (o.initial_temperature)
    s.point.temperature = *o.initial_temperature;
  s.p = m.pressure(s.rho, s.E);

  Mat3 D = Mat3::Zero(), W = Mat3::Zero();
  if (o.path == StrainPath::UniaxialStrain)
    D(0, 0) = rate;
  if (o.path == StrainPath::Shear) {
    D(0, 1) = D(1, 0) = 0.5 * rate;
    W(0, 1) = 0.5 * rate;
    W(1, 0) = -0.5 * rate;
  }
  // Lateral rate of an elastic bar, −ν ε̇: the first guess of uniaxial stress.
  const double K = m.elastic.bulk, G = m.elastic.shear;
  double lateral = -rate * (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G));

  std::vector<DriverRow> rows;
  rows.reserve(o.increments + 1);
  rows.push_back(row_of(s, 0.0, 0.0, rate, 0.0));
  for (int i = 1; i <= o.increments; ++i) {
    // A failed point carries no deviator and no tension: any lateral rate that keeps its
    // pressure at or below 0 leaves it stress-free. Start from the isochoric one, so that the
    // density stops changing rather than drifting with the rate found at failure.
    if (s.point.failed)
      lateral = -0.5 * rate;
    s = o.path == StrainPath::UniaxialStress
            ? uniaxial_stress_increment(m, s, rate, dt, o.band_width, lateral)
            : advance(m, s, D, W, dt, o.band_width);
    const double strain = o.final_strain * i / o.increments;
    rows.push_back(row_of(s, strain / rate, strain, rate, dt));
  }
  return rows;
}

} // namespace sphfem
