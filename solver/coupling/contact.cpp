#include "solver/coupling/contact.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"

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

void Contact::apply(Particles& p, const NeighbourList& list, long long rebuilds,
                    const HexElements& elements, double dt, const std::vector<Index>* only) {
  if (empty())
    return;
  SPHFEM_CHECK(only == nullptr || surface_.empty(),
               "the surface contact is not shared among ranks yet (internal error)");
  const Index rows = p.rows();
#pragma omp parallel for schedule(static) if (rows > parallel_min_items)
  for (Index i = 0; i < rows; ++i)
    p.fc_p[i].setZero();
  if (!kernel_.empty())
    kernel_.apply(p, list, only);
  const ContactTotals surface = surface_.apply(p, list, rebuilds, elements, dt);
  energy_ = surface.energy;
  friction_power_ = surface.friction_power;
  omega2_ = surface.omega2;
}

double Contact::energy(const Particles& p) const {
  const double kernel =
      kernel_.empty() ? 0.0 : deterministic_sum(p.rows(), 0.0, [&](Index i) { return p.phi_p[i]; });
  return kernel + energy_;
}

Vec3 Contact::force_on(const Particles& p, int body) const {
  if (empty() || !in_contact_[body])
    return Vec3::Zero();
  return deterministic_sum(p.rows(), Vec3(Vec3::Zero()), [&](Index i) -> Vec3 {
    return p.body_p[i] == body ? p.fc_p[i] : Vec3(Vec3::Zero());
  });
}

void Contact::persist(StateArchive& a) {
  a.value("contact/energy", energy_);
  a.value("contact/friction_power", friction_power_);
  a.value("contact/omega2", omega2_);
  if (a.reading())
    surface_.forget();
}

} // namespace sphfem
