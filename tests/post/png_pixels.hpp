// Test helpers: a PNG read back with VTK as RGB pixels addressed from the top-left corner, and
// colour search near a point. Every post test runs with DISPLAY unset: charts must need no X.
#pragma once

#include "post/line_chart.hpp"

#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <vector>

namespace sphfem_test {

struct Headless : ::testing::Environment {
  void SetUp() override { unsetenv("DISPLAY"); }
};
inline ::testing::Environment* const headless = ::testing::AddGlobalTestEnvironment(new Headless);

struct Pixels {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb; // row 0 at the top

  sphfem::post::Rgb at(int x, int y) const {
    const unsigned char* p = &rgb[(std::size_t(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
  // Is a pixel within `radius` of (x, y) (rounded) within `tolerance` of colour c per channel?
  bool near(double x, double y, sphfem::post::Rgb c, int radius = 1, int tolerance = 40) const {
    for (int j = int(std::lround(y)) - radius; j <= int(std::lround(y)) + radius; ++j)
      for (int i = int(std::lround(x)) - radius; i <= int(std::lround(x)) + radius; ++i) {
        if (i < 0 || j < 0 || i >= width || j >= height)
          continue;
        const auto p = at(i, j);
        if (std::abs(p.r - c.r) <= tolerance && std::abs(p.g - c.g) <= tolerance &&
            std::abs(p.b - c.b) <= tolerance)
          return true;
      }
    return false;
  }
  double non_white_fraction() const {
    std::size_t n = 0;
    for (std::size_t k = 0; k < rgb.size(); k += 3)
      n += rgb[k] < 250 || rgb[k + 1] < 250 || rgb[k + 2] < 250;
    return double(n) / (rgb.size() / 3);
  }
};

inline Pixels read_png(const std::filesystem::path& file) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  Pixels p;
  int dims[3];
  image->GetDimensions(dims);
  p.width = dims[0];
  p.height = dims[1];
  const int components = image->GetNumberOfScalarComponents();
  p.rgb.resize(std::size_t(p.width) * p.height * 3);
  for (int y = 0; y < p.height; ++y) // VTK counts rows from the bottom
    for (int x = 0; x < p.width; ++x)
      for (int c = 0; c < 3; ++c)
        p.rgb[(std::size_t(y) * p.width + x) * 3 + c] = static_cast<unsigned char>(
            image->GetScalarComponentAsDouble(x, p.height - 1 - y, 0, components >= 3 ? c : 0));
  return p;
}

} // namespace sphfem_test
