// Piecewise-linear time function given as a table of (time, value) points, used to scale
// loads and prescribed velocities. Constant beyond the ends; an empty table means 1.
#pragma once

#include <utility>
#include <vector>

namespace sphfem {

class TimeFunction {
public:
  TimeFunction() = default;
  explicit TimeFunction(std::vector<std::pair<double, double>> table);

  double operator()(double t) const;
  const std::vector<std::pair<double, double>>& table() const { return table_; }

private:
  std::vector<std::pair<double, double>> table_;
};

} // namespace sphfem
