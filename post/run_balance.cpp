// Each rank's cost per frame of a run under the two ownerships, and its CSV and chart
// (run_balance.hpp). Verified by tests/e2e/partition_command_test.cpp.
#include "post/run_balance.hpp"

#include "post/frames.hpp"
#include "post/line_chart.hpp"
#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <string>

namespace sphfem::post {

namespace fs = std::filesystem;

namespace {

double imbalance(const std::vector<double>& cost) {
  const double mean = std::accumulate(cost.begin(), cost.end(), 0.0) / cost.size();
  return mean > 0 ? *std::max_element(cost.begin(), cost.end()) / mean : 1.0;
}

} // namespace

RunBalance run_balance(const fs::path& run_dir, const Decomposition& d, const EntityCosts& costs) {
  RunBalance b;
  const std::size_t np = d.part_p.size(), ne = d.part_e.size();
  Decomposition moved = d; // owners by region, carried from frame to frame
  for (const FrameFiles& files : frame_files(run_dir / "results.pvd")) {
    std::vector<int> neighbours(np, 0);
    std::vector<unsigned char> live_p(np, 0), live_e(ne, ne > 0 ? 1 : 0);
    std::vector<unsigned char> yielding_p(np, 0), yielding_e(ne, 0);
    if (!files.particles.empty()) {
      const auto grid = read_vtu(files.particles);
      const vtkIdType n = grid->GetNumberOfPoints();
      auto* pd = grid->GetPointData();
      auto* id = frame_array(pd, "id", 1, n, files.particles);
      auto* count = frame_array(pd, "neighbours", 1, n, files.particles);
      auto* killed = frame_array(pd, "killed", 1, n, files.particles, false);
      auto* yields = frame_array(pd, "yielding", 1, n, files.particles, false);
      for (vtkIdType k = 0; k < n; ++k) {
        const auto i = static_cast<long long>(id->GetComponent(k, 0));
        SPHFEM_CHECK(i >= 0 && static_cast<std::size_t>(i) < np, files.particles.string(),
                     ": particle id ", i, " is not one of the case's ", np,
                     " particles: the run is not of this case");
        neighbours[static_cast<std::size_t>(i)] = static_cast<int>(count->GetComponent(k, 0));
        live_p[static_cast<std::size_t>(i)] = !killed || killed->GetComponent(k, 0) == 0;
        yielding_p[static_cast<std::size_t>(i)] = yields && yields->GetComponent(k, 0) != 0;
        double x[3];
        grid->GetPoint(k, x);
        int& owner = moved.part_p[static_cast<std::size_t>(i)];
        owner = moved.particle_part_at(Vec3(x[0], x[1], x[2]), owner);
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
      auto* eroded = frame_array(grid->GetCellData(), "eroded", 1, n, files.elements, false);
      for (vtkIdType e = 0; eroded && e < n; ++e)
        live_e[static_cast<std::size_t>(e)] = eroded->GetComponent(e, 0) == 0;
      auto* yields = frame_array(grid->GetCellData(), "yielding", 1, n, files.elements, false);
      for (vtkIdType e = 0; yields && e < n; ++e)
        yielding_e[static_cast<std::size_t>(e)] = yields->GetComponent(e, 0) != 0;
      vtkNew<vtkIdList> ids;
      for (vtkIdType e = 0; e < n; ++e) {
        grid->GetCellPoints(e, ids);
        Vec3 centre = Vec3::Zero();
        for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
          double x[3];
          grid->GetPoint(ids->GetId(k), x);
          centre += Vec3(x[0], x[1], x[2]);
        }
        int& owner = moved.part_e[static_cast<std::size_t>(e)];
        owner = moved.part_at(centre / static_cast<double>(ids->GetNumberOfIds()), owner);
      }
    } else {
      SPHFEM_CHECK(ne == 0, run_dir.string(), ": the run has no element frames, the case has ", ne,
                   " hexahedra");
    }
    b.time_s.push_back(files.time);
    b.cost_s.push_back(part_costs(d, costs, neighbours, live_p, live_e, yielding_p, yielding_e));
    b.imbalance.push_back(imbalance(b.cost_s.back()));
    b.region_cost_s.push_back(
        part_costs(moved, costs, neighbours, live_p, live_e, yielding_p, yielding_e));
    b.region_imbalance.push_back(imbalance(b.region_cost_s.back()));
  }
  return b;
}

void write_run_balance(const RunBalance& b, const fs::path& csv, const fs::path& png) {
  const std::size_t parts = b.cost_s.empty() ? 0 : b.cost_s.front().size();
  std::string text = "time_s,imbalance,region_imbalance";
  for (const char* kind : {"cost_s_rank", "region_cost_s_rank"})
    for (std::size_t q = 0; q < parts; ++q)
      text.append(",").append(kind).append(std::to_string(q));
  text += "\n";
  char number[32];
  const auto add = [&](double value) {
    std::snprintf(number, sizeof number, ",%.9g", value);
    text += number;
  };
  std::vector<double> t_us, smallest[2];
  for (std::size_t f = 0; f < b.time_s.size(); ++f) {
    std::snprintf(number, sizeof number, "%.9g", b.time_s[f]);
    text += number;
    add(b.imbalance[f]);
    add(b.region_imbalance[f]);
    for (const auto* cost : {&b.cost_s[f], &b.region_cost_s[f]})
      for (const double c : *cost)
        add(c);
    text += "\n";
    t_us.push_back(b.time_s[f] * 1e6);
    for (int k = 0; k < 2; ++k) { // the largest over the mean is the imbalance
      const std::vector<double>& cost = k == 0 ? b.cost_s[f] : b.region_cost_s[f];
      const double mean =
          std::accumulate(cost.begin(), cost.end(), 0.0) / static_cast<double>(parts);
      smallest[k].push_back(mean > 0 ? *std::min_element(cost.begin(), cost.end()) / mean : 1.0);
    }
  }
  write_text_atomically(csv, text);

  LineChart chart(900, 500);
  chart.set_title("Cost per step of the ranks, the decomposition of t = 0 kept");
  chart.set_x_label("time (µs)");
  chart.set_y_label("rank's cost / mean");
  chart.add_series("largest, entities kept on their rank", t_us, b.imbalance,
                   {LineChart::palette(0)});
  chart.add_series("smallest, entities kept", t_us, smallest[0],
                   {LineChart::palette(0), 2.0, true});
  chart.add_series("largest, entities owned by their region", t_us, b.region_imbalance,
                   {LineChart::palette(1)});
  chart.add_series("smallest, by region", t_us, smallest[1], {LineChart::palette(1), 2.0, true});
  chart.write_png(png);
}

} // namespace sphfem::post
