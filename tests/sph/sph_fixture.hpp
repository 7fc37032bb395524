// Test helpers: a steel block of SPH particles on a cell-centred lattice, built directly
// (independent of the mesher), and a Case with one such body.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <cmath>

namespace sphfem::test {

inline MaterialSpec steel() {
  return {.name = "steel",
          .model = "elastic",
          .density = 7830.0,
          .youngs_modulus = 207e9,
          .poisson_ratio = 0.3};
}

inline Model lattice_block(const Vec3& size, double dp, double h_factor) {
  Model m;
  m.body_names = {"block"};
  m.spacing_b = {dp};
  const int nx = static_cast<int>(std::lround(size.x() / dp)),
            ny = static_cast<int>(std::lround(size.y() / dp)),
            nz = static_cast<int>(std::lround(size.z() / dp));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        m.x_p.push_back(dp * Vec3(i + 0.5, j + 0.5, k + 0.5));
        m.m_p.push_back(steel().density * dp * dp * dp);
        m.rho_p.push_back(steel().density);
        m.h_p.push_back(h_factor * dp);
        m.body_p.push_back(0);
      }
  return m;
}

inline Case block_case(double dp, double h_factor) {
  Case c;
  c.name = "sph_block";
  c.time = {1.0, 0.9, 1.0, 0.0};
  c.materials = {steel()};
  BodySpec body;
  body.name = "block";
  body.method = Method::Sph;
  body.spacing = dp;
  body.h_factor = h_factor;
  body.material = "steel";
  c.bodies = {body};
  return c;
}

} // namespace sphfem::test
