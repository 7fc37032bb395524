// Recht–Ipson fit (recht_ipson.hpp): grid start, then Levenberg–Marquardt with Marquardt's
// diagonal scaling (the parameters differ by two orders of magnitude) and steps clipped to the
// box.
#include "post/recht_ipson.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphfem::post {

namespace {

using Vector3 = Eigen::Vector3d; // (a, p, vbl)

// (v0^p − vbl^p)^(1/p), 0 for v0 ≤ vbl.
double shape(double v0, double p, double vbl) {
  const double u = std::pow(v0, p) - std::pow(vbl, p);
  return u > 0 ? std::pow(u, 1 / p) : 0.0;
}

struct Data {
  std::vector<double> v0, vr;

  double sse(const Vector3& x) const {
    double s = 0;
    for (std::size_t i = 0; i < v0.size(); ++i) {
      const double r = x[0] * shape(v0[i], x[1], x[2]) - vr[i];
      s += r * r;
    }
    return s;
  }

  // Residuals and their Jacobian with respect to (a, p, vbl).
  void linearise(const Vector3& x, Eigen::VectorXd& r, Eigen::MatrixX3d& J) const {
    const double a = x[0], p = x[1], vbl = x[2];
    const auto n = static_cast<Eigen::Index>(v0.size());
    r.resize(n);
    J.setZero(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double v = v0[i], u = std::pow(v, p) - std::pow(vbl, p);
      if (u <= 0) {
        r[i] = -vr[i];
        continue;
      }
      const double g = std::pow(u, 1 / p);
      const double vbl_log = vbl > 0 ? std::pow(vbl, p) * std::log(vbl) : 0.0;
      r[i] = a * g - vr[i];
      J(i, 0) = g;
      J(i, 1) =
          a * g * (-std::log(u) / (p * p) + (std::pow(v, p) * std::log(v) - vbl_log) / (p * u));
      J(i, 2) = vbl > 0 ? -a * std::pow(g, 1 - p) * std::pow(vbl, p - 1) : 0.0;
    }
  }
};

Vector3 levenberg_marquardt(const Data& d, Vector3 x, const Vector3& lo, const Vector3& hi) {
  double sse = d.sse(x), lambda = 1e-3;
  Eigen::VectorXd r;
  Eigen::MatrixX3d J;
  for (int iteration = 0; iteration < 500 && lambda < 1e12; ++iteration) {
    d.linearise(x, r, J);
    const Eigen::Matrix3d JtJ = J.transpose() * J;
    const Vector3 g = J.transpose() * r;
    const Vector3 diag = JtJ.diagonal().cwiseMax(1e-12 * JtJ.diagonal().maxCoeff() + 1e-300);
    bool accepted = false;
    while (!accepted && lambda < 1e12) {
      Eigen::Matrix3d A = JtJ;
      A.diagonal() += lambda * diag;
      const Vector3 trial = (x - A.ldlt().solve(g)).cwiseMax(lo).cwiseMin(hi);
      const double trial_sse = d.sse(trial);
      if (trial_sse < sse) {
        const bool converged =
            ((trial - x).cwiseQuotient(hi - lo + Vector3::Constant(1e-300))).norm() < 1e-13 ||
            sse - trial_sse < 1e-15 * sse;
        x = trial;
        sse = trial_sse;
        lambda = std::max(lambda / 3, 1e-12);
        accepted = true;
        if (converged)
          return x;
      } else
        lambda *= 4;
    }
  }
  return x;
}

} // namespace

double RechtIpson::operator()(double v0) const {
  return a * shape(v0, p, vbl);
}

std::optional<RechtIpson> fit_recht_ipson(const std::vector<BallisticPoint>& points) {
  Data d;
  double vbl_max = std::numeric_limits<double>::infinity();
  for (const BallisticPoint& b : points)
    if (b.perforated) {
      d.v0.push_back(b.v0);
      d.vr.push_back(b.vr);
      vbl_max = std::min(vbl_max, b.v0);
    }
  if (d.v0.size() < 3)
    return std::nullopt;
  // A non-perforating point above the lowest perforating one (scatter near the limit) cannot
  // bound vbl: the highest one below it does.
  double vbl_min = 0;
  for (const BallisticPoint& b : points)
    if (!b.perforated && b.v0 < vbl_max)
      vbl_min = std::max(vbl_min, b.v0);

  const Vector3 lo(1e-6, 1.0, vbl_min), hi(1.5, 4.0, vbl_max);
  // Grid over (vbl, p); for each, the best a is linear least squares.
  struct Start {
    double sse;
    Vector3 x;
  };
  std::vector<Start> starts;
  constexpr int n_vbl = 41, n_p = 31;
  for (int i = 0; i < n_vbl; ++i)
    for (int j = 0; j < n_p; ++j) {
      const double vbl = vbl_min + (vbl_max - vbl_min) * i / (n_vbl - 1);
      const double p = 1.0 + 3.0 * j / (n_p - 1);
      double gg = 0, gv = 0;
      for (std::size_t k = 0; k < d.v0.size(); ++k) {
        const double g = shape(d.v0[k], p, vbl);
        gg += g * g;
        gv += g * d.vr[k];
      }
      const double a = std::clamp(gg > 0 ? gv / gg : 1.0, lo[0], hi[0]);
      const Vector3 x(a, p, vbl);
      starts.push_back({d.sse(x), x});
    }
  // Several starts guard against a local minimum along the valley p ↔ vbl.
  constexpr std::size_t n_starts = 5;
  std::partial_sort(starts.begin(), starts.begin() + n_starts, starts.end(),
                    [](const Start& s, const Start& t) { return s.sse < t.sse; });
  Vector3 best = starts.front().x;
  double best_sse = starts.front().sse;
  for (std::size_t s = 0; s < n_starts; ++s) {
    const Vector3 x = levenberg_marquardt(d, starts[s].x, lo, hi);
    if (const double sse = d.sse(x); sse < best_sse) {
      best = x;
      best_sse = sse;
    }
  }
  RechtIpson fit;
  fit.a = best[0];
  fit.p = best[1];
  fit.vbl = best[2];
  fit.points = static_cast<int>(d.v0.size());
  fit.rms = std::sqrt(best_sse / fit.points);
  fit.vbl_min = vbl_min;
  fit.vbl_max = vbl_max;
  return fit;
}

} // namespace sphfem::post
