#include "post/csv_chart.hpp"

#include "post/line_chart.hpp"
#include "post/post.hpp"
#include "solver/core/error.hpp"

#include <algorithm>
#include <cmath>

namespace sphfem::post {

CsvChart write_csv_chart(const CsvChartOptions& o) {
  const CsvTable t = read_csv_table(o.csv);
  const std::size_t cx = t.column(o.x), cy = t.column(o.y);
  const std::size_t cg = o.group.empty() ? 0 : t.column(o.group);

  CsvChart out;
  std::vector<std::vector<double>> xs, ys;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const std::string name = o.group.empty() ? o.y : t.rows[r][cg];
    auto it = std::find(out.series.begin(), out.series.end(), name);
    if (it == out.series.end()) {
      out.series.push_back(name);
      xs.emplace_back();
      ys.emplace_back();
      it = out.series.end() - 1;
    }
    const double x = t.number(r, cx), y = t.number(r, cy);
    SPHFEM_CHECK(!(o.log_x && x <= 0), o.csv.string(), ":", t.line_of_row[r], ": column ", o.x,
                 ": ", x, " on a logarithmic axis (expected > 0)");
    SPHFEM_CHECK(!(o.log_y && y <= 0), o.csv.string(), ":", t.line_of_row[r], ": column ", o.y,
                 ": ", y, " on a logarithmic axis (expected > 0)");
    const auto k = std::size_t(it - out.series.begin());
    xs[k].push_back(x);
    ys[k].push_back(y);
    out.points += std::isfinite(x) && std::isfinite(y);
  }

  LineChart chart(o.width, o.height);
  chart.set_title(o.title);
  chart.set_x_label(o.x_label.empty() ? o.x : o.x_label);
  chart.set_y_label(o.y_label.empty() ? o.y : o.y_label);
  chart.set_log_x(o.log_x);
  chart.set_log_y(o.log_y);
  for (std::size_t k = 0; k < out.series.size(); ++k)
    chart.add_series(out.series[k], xs[k], ys[k],
                     {LineChart::palette(k), o.lines ? 2.0 : 0.0, false, 4.0});
  chart.write_png(o.png);
  return out;
}

} // namespace sphfem::post
