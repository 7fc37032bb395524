#include "solver/core/time_function.hpp"

#include <algorithm>

namespace sphfem {

TimeFunction::TimeFunction(std::vector<std::pair<double, double>> table)
    : table_(std::move(table)) {}

double TimeFunction::operator()(double t) const {
  if (table_.empty())
    return 1.0;
  if (t <= table_.front().first)
    return table_.front().second;
  if (t >= table_.back().first)
    return table_.back().second;
  const auto upper =
      std::upper_bound(table_.begin(), table_.end(), t,
                       [](double time, const auto& point) { return time < point.first; });
  const auto lower = upper - 1;
  const double span = upper->first - lower->first;
  const double s = span > 0.0 ? (t - lower->first) / span : 1.0;
  return lower->second + s * (upper->second - lower->second);
}

} // namespace sphfem
