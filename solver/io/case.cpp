// Look-ups by name on a validated Case, and the nose's length.
#include "solver/io/case.hpp"

#include "solver/core/error.hpp"

#include <algorithm>
#include <cmath>

namespace sphfem {

double NoseGeometry::nose_length(double radius) const {
  switch (shape) {
  case Shape::Flat:
    return 0;
  case Shape::Hemispherical:
    return radius;
  case Shape::Conical:
    return length;
  case Shape::Ogival:
    return radius * std::sqrt(4 * crh - 1);
  }
  return 0;
}

double NoseGeometry::radius_at(double z, double radius) const {
  const double ln = nose_length(radius);
  switch (shape) {
  case Shape::Flat:
    return radius;
  case Shape::Hemispherical:
    return std::sqrt(std::max(0.0, radius * radius - (radius - z) * (radius - z)));
  case Shape::Conical:
    return radius * z / ln;
  case Shape::Ogival: {
    const double rho = 2 * crh * radius; // the ogive's arc radius, its centre ρ − R beyond the axis
    return std::sqrt(std::max(0.0, rho * rho - (ln - z) * (ln - z))) - (rho - radius);
  }
  }
  return radius;
}

const MaterialSpec& Case::material(const std::string& name) const {
  const auto found = std::ranges::find(materials, name, &MaterialSpec::name);
  SPHFEM_CHECK(found != materials.end(), "case '", this->name, "' has no material '", name, "'");
  return *found;
}

int Case::body_index(const std::string& name) const {
  const auto found = std::ranges::find(bodies, name, &BodySpec::name);
  return found == bodies.end() ? -1 : static_cast<int>(found - bodies.begin());
}

std::vector<int> Case::body_groups() const {
  std::vector<int> group(bodies.size());
  for (std::size_t b = 0; b < group.size(); ++b)
    group[b] = static_cast<int>(b);
  for (const AttachSpec& a : attachments)
    group[body_index(a.sph_body)] = body_index(a.fem_body);
  return group;
}

} // namespace sphfem
