#include "post/line_chart.hpp"

#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkStdString.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

namespace sphfem::post {

namespace {

constexpr Rgb white{255, 255, 255}, black{0, 0, 0}, grid_grey{225, 225, 225},
    minor_grey{242, 242, 242};
constexpr int dpi = 72; // font sizes are then in pixels

struct Canvas {
  int width, height;
  std::vector<unsigned char> rgb;

  Canvas(int w, int h) : width(w), height(h), rgb(std::size_t(w) * h * 3, 255) {}

  void blend(int x, int y, Rgb c, double alpha) {
    if (x < 0 || y < 0 || x >= width || y >= height || alpha <= 0)
      return;
    unsigned char* p = &rgb[(std::size_t(y) * width + x) * 3];
    const double a = std::min(alpha, 1.0);
    p[0] = static_cast<unsigned char>(std::lround(p[0] + a * (c.r - p[0])));
    p[1] = static_cast<unsigned char>(std::lround(p[1] + a * (c.g - p[1])));
    p[2] = static_cast<unsigned char>(std::lround(p[2] + a * (c.b - p[2])));
  }
  void fill(int x0, int y0, int x1, int y1, Rgb c) { // inclusive corners
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        blend(x, y, c, 1.0);
  }
  void frame(int x0, int y0, int x1, int y1, Rgb c) {
    fill(x0, y0, x1, y0, c);
    fill(x0, y1, x1, y1, c);
    fill(x0, y0, x0, y1, c);
    fill(x1, y0, x1, y1, c);
  }
};

// Text through VTK's FreeType renderer: CPU rasterisation into an RGBA vtkImageData whose
// extent is placed relative to the anchor the justification names.
struct Text {
  vtkNew<vtkTextProperty> property;
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();

  // h: VTK_TEXT_LEFT|CENTERED|RIGHT, v: VTK_TEXT_BOTTOM|CENTERED|TOP, angle in degrees.
  Text(int size, int h, int v, double angle = 0, bool bold = false) {
    SPHFEM_CHECK(renderer, "VTK has no text renderer (RenderingFreeType not linked)");
    property->SetFontFamilyToArial();
    property->SetFontSize(size);
    property->SetColor(0, 0, 0);
    property->SetJustification(h);
    property->SetVerticalJustification(v);
    property->SetOrientation(angle);
    property->SetBold(bold);
  }
  // {xmin, xmax, ymin, ymax} around the anchor, y up.
  std::array<int, 4> box(const std::string& s) {
    std::array<int, 4> b{0, 0, 0, 0};
    if (!s.empty())
      renderer->GetBoundingBox(property, vtkStdString(s), b.data(), dpi, vtkTextRenderer::FreeType);
    return b;
  }
  void draw(Canvas& canvas, const std::string& s, int x, int y) {
    if (s.empty())
      return;
    vtkNew<vtkImageData> image;
    SPHFEM_CHECK(renderer->RenderString(property, vtkStdString(s), image, nullptr, dpi,
                                        vtkTextRenderer::FreeType),
                 "cannot render the text \"", s, "\"");
    int e[6];
    image->GetExtent(e);
    for (int j = e[2]; j <= e[3]; ++j)
      for (int i = e[0]; i <= e[1]; ++i) {
        const auto* p = static_cast<unsigned char*>(image->GetScalarPointer(i, j, 0));
        canvas.blend(x + i, y - j, {p[0], p[1], p[2]}, p[3] / 255.0);
      }
  }
};

// Coverage of one series' polyline: the anti-aliased line is the set of pixels within
// width/2 of a segment, with a one-pixel ramp; max over segments, so joints do not darken.
struct Coverage {
  int width, height;
  std::vector<float> alpha;

  Coverage(int w, int h) : width(w), height(h), alpha(std::size_t(w) * h, 0.f) {}

  // Segment a→b; `s0` is the arc length at a (for dashes); pixels outside `clip` stay empty.
  void segment(double ax, double ay, double bx, double by, double s0, const LineStyle& style,
               const LineChart::Rect& clip) {
    const double hw = style.width / 2, dash = 9, period = 14;
    const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
    const int x0 = std::max(clip.left, int(std::floor(std::min(ax, bx) - hw - 1)));
    const int x1 = std::min(clip.right, int(std::ceil(std::max(ax, bx) + hw + 1)));
    const int y0 = std::max(clip.top, int(std::floor(std::min(ay, by) - hw - 1)));
    const int y1 = std::min(clip.bottom, int(std::ceil(std::max(ay, by) + hw + 1)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double t = len2 > 0 ? std::clamp(((x - ax) * dx + (y - ay) * dy) / len2, 0., 1.) : 0;
        if (style.dashed && std::fmod(s0 + t * std::sqrt(len2), period) > dash)
          continue;
        const double d = std::hypot(x - ax - t * dx, y - ay - t * dy);
        const double a = std::clamp(hw + 0.5 - d, 0., 1.);
        float& slot = alpha[std::size_t(y) * width + x];
        slot = std::max(slot, float(a));
      }
  }
  // A filled dot of `radius` px at (cx, cy), with a one-pixel ramp.
  void dot(double cx, double cy, double radius, const LineChart::Rect& clip) {
    for (int y = std::max(clip.top, int(std::floor(cy - radius - 1)));
         y <= std::min(clip.bottom, int(std::ceil(cy + radius + 1))); ++y)
      for (int x = std::max(clip.left, int(std::floor(cx - radius - 1)));
           x <= std::min(clip.right, int(std::ceil(cx + radius + 1))); ++x) {
        const double a = std::clamp(radius + 0.5 - std::hypot(x - cx, y - cy), 0., 1.);
        float& slot = alpha[std::size_t(y) * width + x];
        slot = std::max(slot, float(a));
      }
  }
  double sum(int x0, int y0, int x1, int y1) const {
    double s = 0;
    for (int y = std::max(y0, 0); y <= std::min(y1, height - 1); ++y)
      for (int x = std::max(x0, 0); x <= std::min(x1, width - 1); ++x)
        s += alpha[std::size_t(y) * width + x];
    return s;
  }
};

double nice(double x) { // the 1, 2, 5 or 10 × 10^k nearest to x
  const double e = std::pow(10.0, std::floor(std::log10(x))), f = x / e;
  return (f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10) * e;
}

std::string tick_label(double v, double step) {
  if (std::abs(v) < 1e-9 * step)
    v = 0;
  char buffer[64];
  const double largest = std::max(std::abs(v), step);
  if (largest >= 1e6 || step < 1e-4)
    std::snprintf(buffer, sizeof buffer, "%.4g", v);
  else
    std::snprintf(buffer, sizeof buffer, "%.*f",
                  std::max(0, int(-std::floor(std::log10(step) + 1e-9))), v);
  std::string s = buffer;
  return s[0] == '-' ? "\u2212" + s.substr(1) : s; // a typographic minus
}

// A polygon filled by its pixel centres (even–odd rule, scanlines), clipped to `clip`.
void fill_polygon(Canvas& canvas, const std::vector<double>& x, const std::vector<double>& y,
                  Rgb colour, const LineChart::Rect& clip) {
  if (std::any_of(x.begin(), x.end(), [](double v) { return !std::isfinite(v); }) ||
      std::any_of(y.begin(), y.end(), [](double v) { return !std::isfinite(v); }))
    return;
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  std::vector<double> crossings;
  for (int row = std::max(clip.top, int(std::ceil(*lo))); row <= std::min(clip.bottom, int(*hi));
       ++row) {
    crossings.clear();
    for (std::size_t i = 0, j = x.size() - 1; i < x.size(); j = i++)
      if ((y[i] <= row) != (y[j] <= row))
        crossings.push_back(x[i] + (row - y[i]) / (y[j] - y[i]) * (x[j] - x[i]));
    std::sort(crossings.begin(), crossings.end());
    for (std::size_t k = 0; k + 1 < crossings.size(); k += 2)
      for (int col = std::max(clip.left, int(std::ceil(crossings[k])));
           col <= std::min(clip.right, int(std::floor(crossings[k + 1]))); ++col)
        canvas.blend(col, row, colour, 1.0);
  }
}

// The colour bar right of the frame: the scale bottom to top, ticks at nice steps, its label.
void colour_bar(Canvas& canvas, const ColourScale& scale, const LineChart::Rect& r) {
  const int left = r.right + 18, right = left + 16;
  for (int row = r.top; row <= r.bottom; ++row)
    canvas.fill(left, row, right, row,
                LineChart::viridis(double(r.bottom - row) / double(r.bottom - r.top)));
  canvas.frame(left, r.top, right, r.bottom, black);
  Text ticks(12, VTK_TEXT_LEFT, VTK_TEXT_CENTERED);
  const double step = nice((scale.max - scale.min) / 5);
  for (double k = std::ceil(scale.min / step - 1e-9); k * step <= scale.max + 1e-9 * step; ++k) {
    const double v = k * step;
    const int row =
        int(std::lround(r.bottom - (v - scale.min) / (scale.max - scale.min) * (r.bottom - r.top)));
    canvas.fill(right, row, right + 4, row, black);
    ticks.draw(canvas, tick_label(v, step), right + 7, row);
  }
  Text label(13, VTK_TEXT_CENTERED, VTK_TEXT_TOP, 90);
  label.draw(canvas, scale.label, right + 50, (r.top + r.bottom) / 2);
}

} // namespace

LineChart::LineChart(int width, int height) : width_(width), height_(height) {
  SPHFEM_CHECK(width >= 200 && height >= 150 && width <= 10000 && height <= 10000, "chart size ",
               width, "x", height, ": expected 200x150 to 10000x10000 pixels");
}

void LineChart::add_series(std::string label, std::vector<double> x, std::vector<double> y,
                           LineStyle style) {
  SPHFEM_CHECK(x.size() == y.size(), "series ", label, ": ", x.size(), " x values but ", y.size(),
               " y values");
  series_.push_back({std::move(label), std::move(x), std::move(y), style});
}

void LineChart::add_patch(std::vector<double> x, std::vector<double> y, double value) {
  SPHFEM_CHECK(x.size() == y.size() && x.size() >= 3, "patch: ", x.size(), " x values and ",
               y.size(), " y values, expected the same number, at least 3");
  patches_.push_back({std::move(x), std::move(y), value});
}

void LineChart::set_colour_scale(ColourScale scale) {
  SPHFEM_CHECK(std::isfinite(scale.min) && std::isfinite(scale.max) && scale.max > scale.min,
               "colour scale ", scale.label, ": [", scale.min, ", ", scale.max,
               "], expected finite ends, min < max");
  scale_ = std::move(scale);
}

LineChart::Rect LineChart::plot_area(int width, int height) {
  return {90, 40, width - 25, height - 60};
}

LineChart::Rect LineChart::frame() const {
  Rect r = plot_area(width_, height_);
  if (scale_)
    r.right -= 95; // the colour bar, its tick labels and its label
  return r;
}

Rgb LineChart::viridis(double t) {
  static constexpr Rgb stops[] = {{68, 1, 84},    {71, 45, 123},  {59, 82, 139},
                                  {44, 114, 142}, {33, 145, 140}, {40, 174, 128},
                                  {94, 201, 98},  {173, 220, 48}, {253, 231, 37}};
  if (std::isnan(t))
    return {160, 160, 160};
  const double s = std::clamp(t, 0.0, 1.0) * (std::size(stops) - 1);
  const std::size_t k = std::min(std::size_t(s), std::size(stops) - 2);
  const double f = s - double(k);
  auto mix = [f](unsigned char a, unsigned char b) {
    return static_cast<unsigned char>(std::lround(a + f * (b - a)));
  };
  return {mix(stops[k].r, stops[k + 1].r), mix(stops[k].g, stops[k + 1].g),
          mix(stops[k].b, stops[k + 1].b)};
}

Rgb LineChart::palette(std::size_t i) {
  static constexpr Rgb colours[] = {{0, 114, 178}, {213, 94, 0},   {0, 158, 115}, {204, 121, 167},
                                    {230, 159, 0}, {86, 180, 233}, {240, 228, 66}};
  return colours[i % std::size(colours)];
}

namespace {
// A value as its axis measures it: log10 on a logarithmic axis, where v ≤ 0 is a gap (NaN).
double on_axis(double v, bool log) {
  if (!log)
    return v;
  return v > 0 ? std::log10(v) : std::numeric_limits<double>::quiet_NaN();
}

// The range covering every finite value of `values` (of all series): nice steps on a linear
// axis, whole decades (a step of one, or more beyond eight decades) on a logarithmic one.
template <class Values> std::array<double, 3> axis_for(const Values& values, bool log) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const std::vector<double>* v : values)
    for (double x : *v)
      if (const double a = on_axis(x, log); std::isfinite(a)) {
        lo = std::min(lo, a);
        hi = std::max(hi, a);
      }
  if (!(lo <= hi))
    lo = 0, hi = 1;
  if (log) {
    lo = std::floor(lo + 1e-9);
    hi = std::max(std::ceil(hi - 1e-9), lo + 1);
    return {lo, hi, std::max(1.0, std::ceil((hi - lo) / 8))};
  }
  if (hi - lo <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) { // constant: centre it
    const double half = lo == 0 ? 1 : 0.1 * std::abs(lo);
    lo -= half;
    hi += half;
  }
  const double step = nice((hi - lo) / 6); // 5 to 10 intervals
  return {std::floor(lo / step + 1e-9) * step, std::ceil(hi / step - 1e-9) * step, step};
}
} // namespace

LineChart::Axis LineChart::x_axis() const {
  std::vector<const std::vector<double>*> v;
  for (const auto& s : series_)
    v.push_back(&s.x);
  for (const auto& p : patches_)
    v.push_back(&p.x);
  const auto a = axis_for(v, log_x_);
  return {a[0], a[1], a[2], log_x_};
}

LineChart::Axis LineChart::y_axis() const {
  std::vector<const std::vector<double>*> v;
  for (const auto& s : series_)
    v.push_back(&s.y);
  for (const auto& p : patches_)
    v.push_back(&p.y);
  const auto a = axis_for(v, log_y_);
  return {a[0], a[1], a[2], log_y_};
}

void LineChart::axes(Axis& x, Axis& y) const {
  x = x_axis();
  y = y_axis();
  if (!equal_aspect_)
    return;
  SPHFEM_CHECK(!log_x_ && !log_y_, "a chart with equal aspect cannot have a logarithmic axis");
  // The axis with more pixels per data unit is widened about its centre to the other's scale.
  const Rect r = frame();
  const double kx = (r.right - r.left) / (x.max - x.min), ky = (r.bottom - r.top) / (y.max - y.min);
  Axis& wide = kx > ky ? x : y;
  const double range = kx > ky ? (r.right - r.left) / ky : (r.bottom - r.top) / kx;
  const double centre = (wide.min + wide.max) / 2;
  wide = {centre - range / 2, centre + range / 2, nice(range / 6)};
}

void LineChart::pixel(double x, double y, double& px, double& py) const {
  const Rect r = frame();
  Axis ax, ay;
  axes(ax, ay);
  px = r.left + (on_axis(x, ax.log) - ax.min) / (ax.max - ax.min) * (r.right - r.left);
  py = r.bottom - (on_axis(y, ay.log) - ay.min) / (ay.max - ay.min) * (r.bottom - r.top);
}

std::vector<unsigned char> LineChart::render() const {
  Canvas canvas(width_, height_);
  const Rect r = frame();
  Axis ax, ay;
  axes(ax, ay);

  // Grid and tick labels at the multiples of the step; on a logarithmic axis at the decades,
  // with a lighter grid at 2…9 × 10^k.
  Text x_ticks(12, VTK_TEXT_CENTERED, VTK_TEXT_TOP), y_ticks(12, VTK_TEXT_RIGHT, VTK_TEXT_CENTERED);
  auto x_line = [&](double v, Rgb grid, int tick, const std::string& label) {
    double px, py;
    pixel(ax.log ? std::pow(10.0, v) : v, 1.0, px, py);
    const int x = int(std::lround(px));
    canvas.fill(x, r.top, x, r.bottom, grid);
    canvas.fill(x, r.bottom, x, r.bottom + tick, black);
    x_ticks.draw(canvas, label, x, r.bottom + 8);
  };
  auto y_line = [&](double v, Rgb grid, int tick, const std::string& label) {
    double px, py;
    pixel(1.0, ay.log ? std::pow(10.0, v) : v, px, py);
    const int y = int(std::lround(py));
    canvas.fill(r.left, y, r.right, y, grid);
    canvas.fill(r.left - tick, y, r.left, y, black);
    y_ticks.draw(canvas, label, r.left - 8, y);
  };
  auto ticks = [&](const Axis& a, auto& line) {
    for (double k = std::ceil(a.min / a.step - 1e-9); k * a.step <= a.max + 1e-9 * a.step; ++k) {
      const double v = k * a.step;
      if (!a.log) {
        line(v, grid_grey, 5, tick_label(v, a.step));
        continue;
      }
      const double decade = std::pow(10.0, v);
      line(v, grid_grey, 5, tick_label(decade, decade));
      for (int m = 2; a.step == 1 && v < a.max && m <= 9; ++m)
        line(v + std::log10(m), minor_grey, 3, "");
    }
  };
  ticks(ax, x_line);
  ticks(ay, y_line);

  // Patches beneath the curves, in the order given (a later one covers an earlier one).
  const Rect inside{r.left + 1, r.top + 1, r.right - 1, r.bottom - 1};
  for (const auto& p : patches_) {
    std::vector<double> px(p.x.size()), py(p.y.size());
    for (std::size_t i = 0; i < p.x.size(); ++i)
      pixel(p.x[i], p.y[i], px[i], py[i]);
    const double t = scale_ ? (p.value - scale_->min) / (scale_->max - scale_->min) : 0.5;
    fill_polygon(canvas, px, py, viridis(t), inside);
  }

  // Curves, each composited once from its coverage.
  Coverage all(width_, height_);
  for (const auto& s : series_) {
    Coverage c(width_, height_);
    double arc = 0, prev_x = 0, prev_y = 0;
    bool prev = false;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        prev = false;
        continue;
      }
      double px, py;
      pixel(s.x[i], s.y[i], px, py);
      if (s.style.marker > 0)
        c.dot(px, py, s.style.marker, inside);
      if (prev && s.style.width > 0) {
        c.segment(prev_x, prev_y, px, py, arc, s.style, inside);
        arc += std::hypot(px - prev_x, py - prev_y);
      }
      prev_x = px, prev_y = py, prev = true;
    }
    for (std::size_t k = 0; k < c.alpha.size(); ++k)
      if (c.alpha[k] > 0) {
        canvas.blend(int(k % width_), int(k / width_), s.style.colour, c.alpha[k]);
        all.alpha[k] = std::max(all.alpha[k], c.alpha[k]);
      }
  }
  canvas.frame(r.left, r.top, r.right, r.bottom, black);

  // Legend in the corner of the plotting area that hides the least of the curves.
  Text legend(13, VTK_TEXT_LEFT, VTK_TEXT_CENTERED);
  if (!series_.empty()) {
    const int line = 20, pad = 8, sample = 30;
    int text_width = 0;
    for (const auto& s : series_) {
      const auto b = legend.box(s.label);
      text_width = std::max(text_width, b[1] - b[0]);
    }
    const int w = pad + sample + 6 + text_width + pad, h = pad + line * int(series_.size()) + pad;
    std::array<std::array<int, 2>, 4> corners{{{r.right - 10 - w, r.top + 10},
                                               {r.left + 10, r.top + 10},
                                               {r.right - 10 - w, r.bottom - 10 - h},
                                               {r.left + 10, r.bottom - 10 - h}}};
    auto hidden = [&](const std::array<int, 2>& c) {
      return all.sum(c[0], c[1], c[0] + w, c[1] + h);
    };
    const auto [x0, y0] = *std::min_element(
        corners.begin(), corners.end(), [&](auto& a, auto& b) { return hidden(a) < hidden(b); });
    canvas.fill(x0, y0, x0 + w, y0 + h, white);
    canvas.frame(x0, y0, x0 + w, y0 + h, {160, 160, 160});
    for (std::size_t i = 0; i < series_.size(); ++i) {
      const int y = y0 + pad + line * int(i) + line / 2;
      Coverage c(width_, height_);
      const Rect all_image{0, 0, width_ - 1, height_ - 1};
      if (series_[i].style.width > 0)
        c.segment(x0 + pad, y, x0 + pad + sample, y, 0, series_[i].style, all_image);
      if (series_[i].style.marker > 0)
        c.dot(x0 + pad + sample / 2.0, y, series_[i].style.marker, all_image);
      for (std::size_t k = 0; k < c.alpha.size(); ++k)
        if (c.alpha[k] > 0)
          canvas.blend(int(k % width_), int(k / width_), series_[i].style.colour, c.alpha[k]);
      legend.draw(canvas, series_[i].label, x0 + pad + sample + 6, y);
    }
  }

  if (scale_)
    colour_bar(canvas, *scale_, r);

  Text title(16, VTK_TEXT_CENTERED, VTK_TEXT_BOTTOM, 0, true);
  title.draw(canvas, title_, (r.left + r.right) / 2, r.top - 12);
  Text x_label(14, VTK_TEXT_CENTERED, VTK_TEXT_BOTTOM);
  x_label.draw(canvas, x_label_, (r.left + r.right) / 2, height_ - 10);
  Text y_label(14, VTK_TEXT_CENTERED, VTK_TEXT_TOP, 90);
  y_label.draw(canvas, y_label_, 12, (r.top + r.bottom) / 2);
  return std::move(canvas.rgb);
}

void LineChart::write_png(const std::filesystem::path& file) const {
  const std::vector<unsigned char> rgb = render();
  vtkNew<vtkImageData> image;
  image->SetDimensions(width_, height_, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* out = static_cast<unsigned char*>(image->GetScalarPointer());
  const std::size_t row = std::size_t(width_) * 3;
  for (int y = 0; y < height_; ++y) // VTK images count rows from the bottom
    std::copy_n(&rgb[std::size_t(height_ - 1 - y) * row], row, out + std::size_t(y) * row);
  write_atomically(file, [&](const std::filesystem::path& temporary) {
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(temporary.string().c_str());
    writer->SetInputData(image);
    writer->Write();
    SPHFEM_CHECK(writer->GetErrorCode() == 0, file.string(), ": cannot write the PNG");
  });
}

} // namespace sphfem::post
