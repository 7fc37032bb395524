// What the contact needs of a distributed run (issue 28): the rows this rank steps, and a way to
// read further than the particle phase does — the surface contact's slaves and faces span the
// ranks' subdomains (coupling/surface_contact.hpp). Null on one process.
#pragma once

#include "solver/core/types.hpp"

#include <functional>
#include <span>
#include <vector>

namespace sphfem {

struct ContactRanks {
  const std::vector<Index>* own = nullptr; // the rows this rank steps, ascending
  std::span<const unsigned char> owns;     // per row: 1 when stepped here
  long long shares = 0;                    // changes when the rows refreshed are chosen anew
  // Refreshes these rows too, now and before every later evaluation until `shares` changes.
  // Collective.
  std::function<void(std::span<const Index>)> read_also;
};

} // namespace sphfem
