// Rounding an exact sum (solver/core/exact_sum.hpp) to a double.
#include "solver/core/exact_sum.hpp"

namespace sphfem {

double ExactSum::value() const {
  if (special_ != 0)
    return special_; // a non-finite term: ±∞ or NaN
  Limbs l = limbs();
  const bool negative = l[limb_count - 1] < 0;
  if (negative) {
    for (auto& limb : l)
      limb = -limb;
    l = of(l, 0).limbs_;
  }
  int top = limb_count - 1;
  while (top >= 0 && l[top] == 0)
    --top;
  if (top < 0)
    return 0.0;
  // The three highest limbs hold at least 65 significant bits; any lower one that is not zero
  // sets the lowest bit (sticky), so that the conversion rounds as the whole sum would.
  const auto at = [&l](int k) { return k >= 0 ? static_cast<Uint128>(l[k]) : 0; };
  Uint128 head = (at(top) << 64) | (at(top - 1) << 32) | at(top - 2);
  for (int k = top - 3; k >= 0; --k)
    if (l[k] != 0) {
      head |= 1;
      break;
    }
  const double magnitude = std::ldexp(static_cast<double>(head), limb_bits * (top - 2) - 1074);
  return negative ? -magnitude : magnitude;
}

} // namespace sphfem
