#include "post/run_balance.hpp"

#include "post/frames.hpp"
#include "post/line_chart.hpp"
#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <string>

namespace sphfem::post {

namespace fs = std::filesystem;

namespace {

// The named one-component array with `count` values, or nullptr when absent and not required.
vtkDataArray* values(vtkDataSetAttributes* data, const char* name, vtkIdType count,
                     const fs::path& file, bool required) {
  vtkDataArray* a = data->GetArray(name);
  SPHFEM_CHECK(a || !required, file.string(), ": no ", name, " array");
  if (a)
    SPHFEM_CHECK(a->GetNumberOfComponents() == 1 && a->GetNumberOfTuples() == count, file.string(),
                 ": array ", name, " has ", a->GetNumberOfTuples(), "×", a->GetNumberOfComponents(),
                 " values, expected ", count, "×1");
  return a;
}

} // namespace

RunBalance run_balance(const fs::path& run_dir, const Decomposition& d, const EntityCosts& costs) {
  RunBalance b;
  const std::size_t np = d.part_p.size(), ne = d.part_e.size();
  for (const FrameFiles& files : frame_files(run_dir / "results.pvd")) {
    std::vector<int> neighbours(np, 0);
    std::vector<unsigned char> live_p(np, 0), live_e(ne, ne > 0 ? 1 : 0);
    if (!files.particles.empty()) {
      const auto grid = read_vtu(files.particles);
      const vtkIdType n = grid->GetNumberOfPoints();
      auto* pd = grid->GetPointData();
      auto* id = values(pd, "id", n, files.particles, true);
      auto* count = values(pd, "neighbours", n, files.particles, true);
      auto* killed = values(pd, "killed", n, files.particles, false);
      for (vtkIdType k = 0; k < n; ++k) {
        const auto i = static_cast<long long>(id->GetComponent(k, 0));
        SPHFEM_CHECK(i >= 0 && static_cast<std::size_t>(i) < np, files.particles.string(),
                     ": particle id ", i, " is not one of the case's ", np,
                     " particles: the run is not of this case");
        neighbours[static_cast<std::size_t>(i)] = static_cast<int>(count->GetComponent(k, 0));
        live_p[static_cast<std::size_t>(i)] = !killed || killed->GetComponent(k, 0) == 0;
      }
    } else {
      SPHFEM_CHECK(np == 0, run_dir.string(), ": the run has no particle frames, the case has ", np,
                   " particles");
    }
    if (!files.elements.empty()) {
      const auto grid = read_vtu(files.elements);
      const vtkIdType n = grid->GetNumberOfCells();
      SPHFEM_CHECK(static_cast<std::size_t>(n) == ne, files.elements.string(), ": ", n,
                   " hexahedra, the case has ", ne, ": the run is not of this case");
      auto* eroded = values(grid->GetCellData(), "eroded", n, files.elements, false);
      for (vtkIdType e = 0; eroded && e < n; ++e)
        live_e[static_cast<std::size_t>(e)] = eroded->GetComponent(e, 0) == 0;
    } else {
      SPHFEM_CHECK(ne == 0, run_dir.string(), ": the run has no element frames, the case has ", ne,
                   " hexahedra");
    }
    const std::vector<double> cost = part_costs(d, costs, neighbours, live_p, live_e);
    const double mean = std::accumulate(cost.begin(), cost.end(), 0.0) / cost.size();
    b.time_s.push_back(files.time);
    b.imbalance.push_back(mean > 0 ? *std::max_element(cost.begin(), cost.end()) / mean : 1.0);
    b.cost_s.push_back(cost);
  }
  return b;
}

void write_run_balance(const RunBalance& b, const fs::path& csv, const fs::path& png) {
  const std::size_t parts = b.cost_s.empty() ? 0 : b.cost_s.front().size();
  std::string text = "time_s,imbalance";
  for (std::size_t q = 0; q < parts; ++q)
    text += ",cost_s_rank" + std::to_string(q);
  text += "\n";
  char number[32];
  const auto add = [&](double value) {
    std::snprintf(number, sizeof number, "%.9g", value);
    text += number;
  };
  std::vector<double> t_us, largest, smallest;
  for (std::size_t f = 0; f < b.time_s.size(); ++f) {
    add(b.time_s[f]);
    text += ",";
    add(b.imbalance[f]);
    for (const double c : b.cost_s[f]) {
      text += ",";
      add(c);
    }
    text += "\n";
    const double mean =
        std::accumulate(b.cost_s[f].begin(), b.cost_s[f].end(), 0.0) / static_cast<double>(parts);
    t_us.push_back(b.time_s[f] * 1e6);
    largest.push_back(b.imbalance[f]);
    smallest.push_back(mean > 0 ? *std::min_element(b.cost_s[f].begin(), b.cost_s[f].end()) / mean
                                : 1.0);
  }
  write_text_atomically(csv, text);

  LineChart chart(900, 500);
  chart.set_title("Cost per step of the ranks, each entity kept on its rank of t = 0");
  chart.set_x_label("time (µs)");
  chart.set_y_label("rank's cost / mean");
  chart.add_series("largest (the imbalance)", t_us, largest, {LineChart::palette(0)});
  chart.add_series("smallest", t_us, smallest, {LineChart::palette(1)});
  chart.write_png(png);
}

} // namespace sphfem::post
