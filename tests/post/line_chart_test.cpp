// LineChart (post/line_chart.hpp), drawn with DISPLAY unset: curves land on the pixels their data
// name (checked against the frame, not against the chart's own mapping), dashes leave gaps, a
// NaN breaks a line, text is drawn, and the PNG read back equals the rendered buffer.
#include "png_pixels.hpp"

#include "post/line_chart.hpp"
#include "solver/core/error.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include <unistd.h>

using sphfem::post::LineChart;
using sphfem::post::Rgb;

namespace {

constexpr int W = 500, H = 360;

// Pixels of the rendered buffer.
sphfem_test::Pixels rendered(const LineChart& chart) {
  return {chart.width(), chart.height(), chart.render()};
}

// Data x in [0, 10], y in [-100, 0] give exactly those axes (steps 2 and 20), so a point's pixel
// follows from the frame alone.
void expected_pixel(double x, double y, double& px, double& py) {
  const auto r = LineChart::plot_area(W, H);
  px = r.left + x / 10 * (r.right - r.left);
  py = r.top + -y / 100 * (r.bottom - r.top);
}

LineChart diagonal_chart(const Rgb& colour) {
  LineChart chart(W, H);
  std::vector<double> x, y;
  for (int i = 0; i <= 50; ++i) {
    x.push_back(0.2 * i);
    y.push_back(-10 * x.back()); // 0 … −100
  }
  chart.add_series("diagonal", x, y, {colour, 2.0, false});
  return chart;
}

} // namespace

TEST(LineChart, MapsDataToTheFrame) {
  const LineChart chart = diagonal_chart(LineChart::palette(0));
  for (double x : {0.0, 2.5, 5.0, 10.0}) {
    double px, py, ex, ey;
    chart.pixel(x, -10 * x, px, py);
    expected_pixel(x, -10 * x, ex, ey);
    EXPECT_NEAR(px, ex, 1e-9);
    EXPECT_NEAR(py, ey, 1e-9);
  }
}

TEST(LineChart, CurvePixelsLieWhereTheDataSay) {
  const Rgb blue = LineChart::palette(0);
  const auto pixels = rendered(diagonal_chart(blue));
  ASSERT_EQ(pixels.rgb.size(), std::size_t(W) * H * 3);
  for (double x = 0.5; x < 10; x += 0.5) {
    double px, py;
    expected_pixel(x, -10 * x, px, py);
    // A 2 px line: its colour within a pixel of the exact point, and not 8 px above or below.
    EXPECT_TRUE(pixels.near(px, py, blue, 1)) << "x = " << x;
    EXPECT_FALSE(pixels.near(px, py - 8, blue, 2)) << "x = " << x;
    EXPECT_FALSE(pixels.near(px, py + 8, blue, 2)) << "x = " << x;
  }
}

TEST(LineChart, DashedLineHasGapsAndNanBreaksALine) {
  LineChart chart = diagonal_chart(LineChart::palette(0));
  const Rgb black{0, 0, 0}, orange = LineChart::palette(1);
  chart.add_series("dashed", {0, 10}, {-80, -80}, {black, 2.0, true});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  chart.add_series("broken", {0, 4, 5, 6, 10}, {-30, -30, nan, -30, -30}, {orange, 2.0, false});
  const auto pixels = rendered(chart);
  int on = 0, off = 0;
  for (double x = 1; x < 9; x += 0.05) {
    double px, py;
    expected_pixel(x, -80, px, py);
    (pixels.near(px, py, black, 0, 60) ? on : off)++;
  }
  EXPECT_GT(on, 40); // dashes 9 px, gaps 5 px
  EXPECT_GT(off, 20);
  double px, py;
  expected_pixel(2, -30, px, py);
  EXPECT_TRUE(pixels.near(px, py, orange, 1));
  expected_pixel(5, -30, px, py); // the gap between x = 4 and 6
  EXPECT_FALSE(pixels.near(px, py, orange, 1));
}

TEST(LineChart, DrawsText) {
  LineChart plain = diagonal_chart(LineChart::palette(0)), titled = plain;
  titled.set_title("tip.vz");
  titled.set_x_label("time (\u00b5s)");
  const auto a = rendered(plain), b = rendered(titled);
  const auto r = LineChart::plot_area(W, H);
  auto ink = [&](const sphfem_test::Pixels& p, int y0, int y1) {
    int n = 0;
    for (int y = y0; y <= y1; ++y)
      for (int x = r.left + 10; x < W; ++x) // right of the y axis's tick labels
        n += p.at(x, y).r < 128;
    return n;
  };
  EXPECT_EQ(ink(a, 0, r.top - 3), 0);
  EXPECT_GT(ink(b, 0, r.top - 3), 20);                          // the title above the frame
  EXPECT_GT(ink(b, H - 25, H - 1), ink(a, H - 25, H - 1) + 20); // the x label below it
}

TEST(LineChart, ConstantAndEmptyDataStillGiveAxes) {
  LineChart chart(W, H);
  chart.add_series("flat", {0, 1, 2}, {5, 5, 5}, {LineChart::palette(0), 2.0, false});
  double px, py;
  chart.pixel(1, 5, px, py);
  const auto r = LineChart::plot_area(W, H);
  EXPECT_NEAR(py, (r.top + r.bottom) / 2.0, 1.0); // a constant sits mid-height
  EXPECT_GT(rendered(chart).non_white_fraction(), 0.01);
  EXPECT_GT(rendered(LineChart(W, H)).non_white_fraction(), 0.005); // frame and ticks only
}

TEST(LineChart, PngReadsBackAsRendered) {
  const LineChart chart = diagonal_chart(LineChart::palette(0));
  const auto file = std::filesystem::temp_directory_path() /
                    ("sphfem_line_chart_test_" + std::to_string(::getpid()) + ".png");
  chart.write_png(file);
  const auto png = sphfem_test::read_png(file);
  EXPECT_EQ(png.width, W);
  EXPECT_EQ(png.height, H);
  EXPECT_EQ(png.rgb, chart.render()); // same orientation, lossless
  std::filesystem::remove(file);
}

TEST(LineChart, RejectsSillySizes) {
  EXPECT_THROW(LineChart(10, 10), sphfem::Error);
}

// Logarithmic axes: whole decades, each the same width, so a power law is a straight line.
TEST(LineChart, LogAxesSpanDecadesAndDrawPowerLawsStraight) {
  LineChart chart(W, H);
  chart.set_log_x(true);
  chart.set_log_y(true);
  std::vector<double> x, y;
  for (double e = -0.5; e <= 2.4; e += 0.01) { // x from 0.32 to 250, y = x^−2 from 10 to 1.6e−5
    x.push_back(std::pow(10.0, e));
    y.push_back(1.0 / (x.back() * x.back()));
  }
  const Rgb blue = LineChart::palette(0);
  chart.add_series("x^-2", x, y, {blue, 2.0, false});
  // x spans 10^−1 … 10^3 (4 decades), y 10^−5 … 10^1 (6 decades).
  const auto r = LineChart::plot_area(W, H);
  auto expected = [&](double xv, double yv, double& px, double& py) {
    px = r.left + (std::log10(xv) + 1) / 4 * (r.right - r.left);
    py = r.bottom - (std::log10(yv) + 5) / 6 * (r.bottom - r.top);
  };
  const auto pixels = rendered(chart);
  for (double xv : {0.5, 1.0, 3.0, 10.0, 42.0, 200.0}) {
    double px, py, ex, ey;
    chart.pixel(xv, 1 / (xv * xv), px, py);
    expected(xv, 1 / (xv * xv), ex, ey);
    EXPECT_NEAR(px, ex, 1e-9) << xv;
    EXPECT_NEAR(py, ey, 1e-9) << xv;
    EXPECT_TRUE(pixels.near(ex, ey, blue, 1)) << xv;
  }
  // The straight line between the ends (independent of the mapping): its midpoint is drawn.
  double ax, ay, bx, by;
  expected(x.front(), y.front(), ax, ay);
  expected(x.back(), y.back(), bx, by);
  EXPECT_TRUE(pixels.near((ax + bx) / 2, (ay + by) / 2, blue, 1));
}

TEST(LineChart, NonPositiveValuesBreakALogLine) {
  LineChart chart(W, H);
  chart.set_log_y(true);
  const Rgb orange = LineChart::palette(1);
  chart.add_series("gap", {0, 4, 5, 6, 10}, {10, 10, 0, 10, 10}, {orange, 2.0, false});
  chart.add_series("span", {0, 10}, {1, 100}, {LineChart::palette(0), 2.0, false});
  const auto pixels = rendered(chart);
  double px, py;
  chart.pixel(2, 10, px, py);
  EXPECT_TRUE(pixels.near(px, py, orange, 1));
  chart.pixel(5, 10, px, py); // between x = 4 and 6 the zero broke the line
  EXPECT_FALSE(pixels.near(px, py, orange, 1));
}

TEST(LineChart, EqualAspectWithALogAxisIsAnError) {
  LineChart chart = diagonal_chart(LineChart::palette(0));
  chart.set_equal_aspect(true);
  chart.set_log_x(true);
  EXPECT_THROW(chart.render(), sphfem::Error);
}

// A field: patches take the colour of their value on the scale (viridis: its published ends and
// middle, #440154, #21918C, #FDE725), values beyond the scale its end colours; the colour bar's
// margin narrows the frame, and the bar runs from the low colour at the bottom to the high one.
TEST(LineChart, PatchesTakeTheirScaleColourBesideAColourBar) {
  EXPECT_EQ(LineChart::viridis(0).r, 0x44);
  EXPECT_EQ(LineChart::viridis(0).b, 0x54);
  EXPECT_EQ(LineChart::viridis(0.5).g, 0x91);
  EXPECT_EQ(LineChart::viridis(1).g, 0xE7);
  EXPECT_EQ(LineChart::viridis(7).r, LineChart::viridis(1).r); // clamped

  LineChart chart(W, H);
  chart.set_colour_scale({"strain (-)", 0, 2});
  chart.add_patch({0, 4, 4, 0}, {0, 0, 4, 4}, 1);     // the middle of the scale
  chart.add_patch({6, 10, 10, 6}, {0, 0, 4, 4}, 9);   // beyond it: the top colour
  chart.add_patch({0, 10, 10, 0}, {6, 6, 10, 10}, 0); // the bottom colour
  const auto frame = chart.frame(), area = LineChart::plot_area(W, H);
  EXPECT_EQ(frame.right, area.right - 95);
  const auto pixels = rendered(chart);
  auto same = [&](double x, double y, Rgb c) {
    double px, py;
    chart.pixel(x, y, px, py);
    const Rgb p = pixels.at(int(std::lround(px)), int(std::lround(py)));
    return p.r == c.r && p.g == c.g && p.b == c.b;
  };
  EXPECT_TRUE(same(1.3, 1.3, LineChart::viridis(0.5)));
  EXPECT_TRUE(same(8.7, 2.7, LineChart::viridis(1)));
  EXPECT_TRUE(same(3.3, 8.1, LineChart::viridis(0)));
  EXPECT_TRUE(same(5.1, 2.1, Rgb{255, 255, 255})); // between the patches, off the grid lines
  const int bar = frame.right + 26;
  EXPECT_TRUE(pixels.near(bar, frame.bottom - 2, LineChart::viridis(0), 1, 10));
  EXPECT_TRUE(pixels.near(bar, frame.top + 2, LineChart::viridis(1), 1, 10));

  EXPECT_THROW(chart.add_patch({0, 1}, {0, 1}, 0), sphfem::Error);
  EXPECT_THROW(chart.set_colour_scale({"flat", 1, 1}), sphfem::Error);
}
