#include "solver/coupling/contact.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/parallel/ranks.hpp"

#include <array>
#include <cmath>

namespace sphfem {

Contact::Contact(const Case& c, const Model& model, const Particles& p,
                 const BackgroundParticles& background, const HexElements& elements)
    : kernel_(c), surface_(c, model, p, background, elements) {
  in_contact_.assign(c.bodies.size(), 0);
  for (const ContactSpec& spec : c.contacts)
    for (const std::string& name : spec.bodies)
      in_contact_[c.body_index(name)] = 1;
}

void Contact::apply(Particles& p, const NeighbourList& list, long long lists,
                    const HexElements& elements, double dt, const ContactRanks* ranks) {
  if (empty())
    return;
  const Index rows = p.rows();
#pragma omp parallel for schedule(static) if (rows > parallel_min_items)
  for (Index i = 0; i < rows; ++i) {
    p.fc_p[i].setZero();
    p.phi_p[i] = 0;
  }
  if (!kernel_.empty())
    kernel_.apply(p, list, ranks != nullptr ? ranks->own : nullptr);
  ContactTotals surface = surface_.apply(p, list, lists, elements, dt, ranks);
  if (ranks != nullptr && !surface_.empty()) {
    ranks::sum_exactly(std::span(&surface.friction_power, 1));
    surface.omega2 = ranks::max(surface.omega2);
  }
  friction_power_ = surface.friction_power.value();
  omega2_ = surface.omega2;
}

ExactSum Contact::energy(const Particles& p, IndexRange rows) const {
  return exact_sums<1>(rows, [&](Index i) { return std::array{p.phi_p[i]}; })[0];
}

ExactSums<3> Contact::force_on(const Particles& p, int body, IndexRange rows) const {
  if (empty() || !in_contact_[body])
    return {};
  return exact_sums<3>(rows, [&](Index i) {
    const Vec3 f = p.body_p[i] == body ? p.fc_p[i] : Vec3(Vec3::Zero());
    return std::array{f.x(), f.y(), f.z()};
  });
}

void Contact::persist(StateArchive& a) {
  a.value("contact/friction_power", friction_power_);
  a.value("contact/omega2", omega2_);
  if (a.reading())
    surface_.forget();
}

} // namespace sphfem
