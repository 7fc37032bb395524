// The strain-rate term shared by the Johnson–Cook flow stress and its fracture strain
// (METHOD.md §5): Børvik's power form (1 + ṙ*)^C, or the classic 1 + C ln ṙ* with ṙ* clamped
// at 1 so that the term never drops below 1 (the fracture term with C = D4 < 0 never rises
// above 1).
#pragma once

#include <algorithm>
#include <cmath>

namespace sphfem {

enum class RateForm { Power, Log };

// The term at the dimensionless rate ṙ* = ṙ/ṗ0 ≥ 0.
inline double rate_term(RateForm form, double C, double ratio) {
  return form == RateForm::Power ? std::pow(1.0 + ratio, C)
                                 : 1.0 + C * std::log(std::max(ratio, 1.0));
}

// The term and its derivative with respect to ṙ*, from one power evaluation.
struct RateTerm {
  double value;
  double slope;
};
inline RateTerm rate_term_and_slope(RateForm form, double C, double ratio) {
  if (form == RateForm::Power) {
    const double value = std::pow(1.0 + ratio, C);
    return {value, C * value / (1.0 + ratio)};
  }
  return {1.0 + C * std::log(std::max(ratio, 1.0)), ratio > 1.0 ? C / ratio : 0.0};
}

} // namespace sphfem
