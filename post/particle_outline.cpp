#include "post/particle_outline.hpp"

#include "solver/core/error.hpp"

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkMarchingSquares.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStripper.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sphfem::post {

std::vector<std::vector<long long>> chain_segments(vtkPolyData* lines) {
  vtkNew<vtkStripper> stripper;
  stripper->SetInputData(lines);
  stripper->JoinContiguousSegmentsOn();
  stripper->SetMaximumLength(100000); // points per polyline; the default 1000 splits long ones
  stripper->Update();
  std::vector<std::vector<long long>> out;
  vtkCellArray* cells = stripper->GetOutput()->GetLines();
  vtkIdType n;
  const vtkIdType* ids;
  for (cells->InitTraversal(); cells->GetNextCell(n, ids);)
    out.emplace_back(ids, ids + n);
  return out;
}

std::vector<Polyline2> particle_outline(const std::vector<Eigen::Vector2d>& x,
                                        const std::vector<double>& area, double spacing) {
  SPHFEM_CHECK(x.size() == area.size(), "particle outline: ", x.size(), " positions but ",
               area.size(), " areas");
  SPHFEM_CHECK(spacing > 0 && std::isfinite(spacing), "particle outline: spacing ", spacing,
               " m: expected > 0");
  if (x.empty())
    return {};
  const double sigma = spacing / 2, reach = 4 * sigma; // the Gaussian beyond 4σ is < 4e-4
  Eigen::Vector2d lo = x[0], hi = x[0];
  for (const auto& p : x) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo.array() -= 3 * spacing;
  hi.array() += 3 * spacing;
  // Δp/6 resolves the 1/2 level to ~1 % of Δp with linear interpolation; coarser only when
  // the grid would exceed 2e7 points (a section much wider than 700 spacings).
  const Eigen::Vector2d extent = hi - lo;
  const double cell = std::max(spacing / 6, std::sqrt(extent.x() * extent.y() / 2e7));
  const int nx = int(std::ceil(extent.x() / cell)) + 1, ny = int(std::ceil(extent.y() / cell)) + 1;

  vtkNew<vtkImageData> image;
  image->SetDimensions(nx, ny, 1);
  image->SetOrigin(lo.x(), lo.y(), 0);
  image->SetSpacing(cell, cell, cell);
  vtkNew<vtkDoubleArray> field;
  field->SetName("indicator");
  field->SetNumberOfTuples(vtkIdType(nx) * ny);
  field->FillValue(0.0);
  double* f = field->GetPointer(0);
  const double norm = 1 / (2 * std::numbers::pi * sigma * sigma);
  const int r = int(std::ceil(reach / cell));
  for (std::size_t p = 0; p < x.size(); ++p) {
    const int ci = int(std::lround((x[p].x() - lo.x()) / cell));
    const int cj = int(std::lround((x[p].y() - lo.y()) / cell));
    for (int j = std::max(cj - r, 0); j <= std::min(cj + r, ny - 1); ++j)
      for (int i = std::max(ci - r, 0); i <= std::min(ci + r, nx - 1); ++i) {
        const double dx = lo.x() + i * cell - x[p].x(), dy = lo.y() + j * cell - x[p].y();
        const double d2 = dx * dx + dy * dy;
        if (d2 <= reach * reach)
          f[std::size_t(j) * nx + i] += area[p] * norm * std::exp(-d2 / (2 * sigma * sigma));
      }
  }
  image->GetPointData()->SetScalars(field);

  vtkNew<vtkMarchingSquares> contour;
  contour->SetInputData(image);
  contour->SetValue(0, 0.5);
  contour->Update();
  vtkPolyData* lines = contour->GetOutput();
  std::vector<Polyline2> out;
  for (const auto& ids : chain_segments(lines)) {
    Polyline2 line;
    for (long long id : ids) {
      double p[3];
      lines->GetPoint(id, p);
      line.emplace_back(p[0], p[1]);
    }
    if (line.size() > 1 && (line.front() - line.back()).norm() > 1e-9 * spacing)
      line.push_back(line.front()); // the grid's margin closes every level line
    out.push_back(std::move(line));
  }
  return out;
}

} // namespace sphfem::post
