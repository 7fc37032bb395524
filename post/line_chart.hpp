// LineChart: a 2-D line chart — frame, ticks, grid, anti-aliased polylines, legend — drawn on
// the CPU into an RGB buffer and written as PNG. It needs no OpenGL and no X display, so it
// works on servers and in CI: Debian's VTK renders vtkChartXY only through an X display
// (../shared/PLATFORM.md). Text is rasterised by VTK's FreeType text renderer (vtkTextRenderer
// draws into a vtkImageData, no render window); the PNG is written by vtkPNGWriter. The font is
// VTK's embedded Arial: no font files needed; it has µ and − but no Greek (labels say szz, not
// σzz). vtkTextRenderer, unlike VTK 9.1's vtkFreeTypeTools string calls, decodes UTF-8.
// Pixel coordinates: x to the right, y down from the top-left corner, as the PNG is viewed;
// integer coordinates are pixel centres. Axes span "nice" ranges (steps 1, 2, 5 × 10^k) that
// cover every finite point; a non-finite value breaks its line. With equal aspect on, one data
// unit spans as many pixels on both axes (sections, shapes), the shorter range widened about its
// centre. A series may draw dots at its points (markers) with or without the line between them.
// Either axis may be logarithmic: it then spans whole decades, labelled at each power of ten and
// gridded at 2…9 × 10^k, and a value ≤ 0 breaks its line as a non-finite one does.
// A field: filled polygons (patches, in data units, beneath the curves) coloured by a value on a
// colour scale (viridis, sampled at nine stops and interpolated linearly; values outside the
// scale take its end colours), with a colour bar in a right margin that narrows the frame.
// Verified by tests/post/line_chart_test.cpp.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sphfem::post {

struct Rgb {
  unsigned char r = 0, g = 0, b = 0;
};

struct LineStyle {
  Rgb colour;
  double width = 2.0; // px; 0: no line, only markers
  bool dashed = false;
  double marker = 0; // radius of a filled dot at each point, px; 0: none
};

// The field's colour scale: its label (with the unit) and the values at its two ends.
struct ColourScale {
  std::string label;
  double min = 0, max = 1;
};

class LineChart {
public:
  struct Rect {
    int left, top, right, bottom; // the frame's pixel columns and rows
  };

  LineChart(int width, int height);

  void set_title(std::string title) { title_ = std::move(title); }
  void set_x_label(std::string label) { x_label_ = std::move(label); }
  void set_y_label(std::string label) { y_label_ = std::move(label); }
  void add_series(std::string label, std::vector<double> x, std::vector<double> y, LineStyle style);
  void set_equal_aspect(bool on) { equal_aspect_ = on; }
  // A polygon (closed implicitly; at least three vertices) filled with the colour of `value`.
  void add_patch(std::vector<double> x, std::vector<double> y, double value);
  void set_colour_scale(ColourScale scale);
  // Logarithmic axes (not with equal aspect).
  void set_log_x(bool on) { log_x_ = on; }
  void set_log_y(bool on) { log_y_ = on; }

  int width() const { return width_; }
  int height() const { return height_; }
  // The frame of the plotting area: fixed margins, so it depends only on the image size.
  static Rect plot_area(int width, int height);
  // This chart's frame: plot_area, less the colour bar's margin if there is a colour scale.
  Rect frame() const;
  // Where the data point (x, y) lands on the image.
  void pixel(double x, double y, double& px, double& py) const;

  // width × height × 3 bytes, RGB, row 0 at the top.
  std::vector<unsigned char> render() const;
  void write_png(const std::filesystem::path& file) const;

  // Colour-blind-safe line colours (Okabe–Ito, less the black kept for references), cycling.
  static Rgb palette(std::size_t i);
  // The colour of the fraction t of a colour scale (clamped to [0, 1]; NaN: grey).
  static Rgb viridis(double t);

private:
  // A logarithmic axis holds decade exponents: min, max and step are those of log10 of the data.
  struct Axis {
    double min, max, step;
    bool log = false;
  };
  struct Series {
    std::string label;
    std::vector<double> x, y;
    LineStyle style;
  };

  struct Patch {
    std::vector<double> x, y;
    double value;
  };

  Axis x_axis() const;
  Axis y_axis() const;
  void axes(Axis& x, Axis& y) const; // x_axis() and y_axis(), widened for equal aspect

  int width_, height_;
  std::string title_, x_label_, y_label_;
  std::vector<Series> series_;
  std::vector<Patch> patches_;
  std::optional<ColourScale> scale_;
  bool equal_aspect_ = false;
  bool log_x_ = false, log_y_ = false;
};

} // namespace sphfem::post
