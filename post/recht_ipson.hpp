// Recht–Ipson ballistic curve vr = a (v0^p − vbl^p)^(1/p) for v0 > vbl, 0 below (Recht &
// Ipson 1963, as fitted by Børvik et al. to the Weldox 460 E plates: a = 0.783, p = 2.24,
// vbl = 184.5 m/s). The fit is a least-squares fit on vr to the perforating points by
// Levenberg–Marquardt with box constraints (a in (0, 1.5], p in [1, 4], vbl between the highest
// non-perforating and the lowest perforating impact velocity), started from the best point of a
// grid over (vbl, p) with a solved linearly. Velocities in m/s.
// Verified by tests/post/sweep_test.cpp.
#pragma once

#include <optional>
#include <vector>

namespace sphfem::post {

struct BallisticPoint {
  double v0 = 0; // impact velocity, m/s
  double vr = 0; // residual velocity, m/s (0 without perforation)
  bool perforated = false;
};

struct RechtIpson {
  double a = 1, p = 2, vbl = 0;    // vbl: ballistic limit, m/s
  double rms = 0;                  // rms residual on vr over the fitted points, m/s
  int points = 0;                  // perforating points fitted
  double vbl_min = 0, vbl_max = 0; // the bracket vbl was held in, m/s

  double operator()(double v0) const;
};

// The fit to `points` (the perforating ones; the others bound vbl from below). Empty with fewer
// than three perforating points: three parameters need three values.
std::optional<RechtIpson> fit_recht_ipson(const std::vector<BallisticPoint>& points);

} // namespace sphfem::post
