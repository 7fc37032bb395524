// SPH particles of one body on a cubic lattice of spacing Δp (METHOD.md §2), and the particle
// faces of a box body.
//
// Box, lattice centred (the default): n_i = max(1, round(L_i / Δp)) particles per direction at
//   min + (k + ½)·L_i / n_i, so the cells tile the box exactly. When L_i / Δp is not an integer
//   the spacing in that direction is L_i / n_i instead of Δp (within a factor 1 ± 1/(2 n_i) of
//   it). Particle volume is the product of the three spacings (Δp³ when every L_i is a multiple
//   of Δp), so the total mass is exactly ρ0 · box volume.
// Box, lattice nodes: the same n_i cells per direction, but n_i + 1 particles per direction on
//   the cell corners min + k·L_i / n_i, k = 0 … n_i: the nodes of the hex mesh of the same box
//   with element_size Δp, so SPH and FE probes can sit at identical points. Each particle's
//   volume is its node's lumped (row-sum) volume, the product over the three directions of its
//   tributary length (L_i / n_i inside, half of it at the two ends): the lumped nodal masses of
//   that hex mesh, so the total mass is again exactly ρ0 · box volume. Surface particles carry
//   half (face), quarter (edge) or eighth (corner) masses, so their volume m/ρ is smaller than
//   Δp³. This is the arrangement of Zhang et al.'s SPH bar (6 × 6 × 51 particles at 1 mm on a
//   5 × 5 mm bar).
// Box faces (both lattices): Model::particle_faces["<body>/<face>"] for xmin … zmax holds the
//   outermost particle layer along the face (nodes: the particles on the face; centred: the
//   first layer, half a spacing inside), each with its tributary area (the product of its two
//   in-plane tributary lengths, so the areas of a face sum to its area exactly up to rounding),
//   and the outward unit normal. Cylinders and files get no particle faces.
// Cylinder and file: cells of exactly Δp covering the body's bounding box, centred on it
//   (covering_lattice); a particle at each cell centre inside the body. Cylinder: radial distance
//   < R and axial coordinate in [0, L) from the base. File: enclosed by the triangulated boundary
//   of one of the file's volumes (solid_file.cpp, ray_parity.cpp). Each particle has volume Δp³,
//   so the total mass of a curved body is the lattice-count approximation ρ0 · N · Δp³ of
//   ρ0 · V (the count error is a boundary effect of relative size ~Δp / body size).
// Rings and quarter cylinders are FE-only geometries: filling one is an error.
// Every particle: mass ρ0 · volume, density ρ0, smoothing length h = h_factor · Δp (the nominal
// Δp, also for a box whose spacing was adjusted). Verified by tests/mesher/lattice_test.cpp.
#include "mesher/lattice.hpp"

#include "solver/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphfem::mesher {
namespace {

// Particle indices are Index (int32), so no lattice may have more cells.
constexpr double max_cells = std::numeric_limits<Index>::max();

// Checks the cell counts per direction before they are converted to Index.
void check_cell_count(const std::array<double, 3>& cells, double spacing) {
  const double total = cells[0] * cells[1] * cells[2];
  SPHFEM_CHECK(std::ranges::all_of(cells, [](double n) { return n >= 1 && n <= max_cells; }) &&
                   total <= max_cells,
               "spacing ", spacing, " m is too fine: ", total, " lattice cells (at most ",
               max_cells, ")");
}

// The spacing must not exceed the body's smallest extent (up to rounding: 1.001 − 1 < 0.001).
void check_fits(double spacing, double smallest, const char* what) {
  SPHFEM_CHECK(spacing <= smallest * (1 + 1e-9), "spacing ", spacing,
               " m is larger than the body (", what, " ", smallest, " m)");
}

// Adds particles of one body, all alike but for their positions.
class ParticleSink {
public:
  ParticleSink(Model& model, int body_id, double volume, double density, double h)
      : model_(model), body_id_(body_id), mass_(density * volume), density_(density), h_(h),
        first_(model.x_p.size()) {}

  void reserve(std::size_t count) {
    for (auto* v : {&model_.m_p, &model_.rho_p, &model_.h_p})
      v->reserve(model_.x_p.size() + count);
    model_.x_p.reserve(model_.x_p.size() + count);
    model_.body_p.reserve(model_.x_p.size() + count);
  }
  void add(const Vec3& x) { add(x, mass_); }
  void add(const Vec3& x, double mass) {
    model_.x_p.push_back(x);
    model_.m_p.push_back(mass);
    model_.rho_p.push_back(density_);
    model_.h_p.push_back(h_);
    model_.body_p.push_back(body_id_);
  }
  std::size_t first() const { return first_; }
  std::size_t added() const { return model_.x_p.size() - first_; }

private:
  Model& model_;
  int body_id_;
  double mass_, density_, h_;
  std::size_t first_;
};

// A box's particles per direction: coordinates x[a] and tributary lengths w[a] (each particle's
// share of the box's length along a). Particle (i, j, k) sits at (x[0][i], x[1][j], x[2][k]) with
// volume w[0][i]·w[1][j]·w[2][k] and flat index (i·n1 + j)·n2 + k, nd = x[d].size().
struct BoxGrid {
  std::array<std::vector<double>, 3> x, w;

  std::size_t size(int a) const { return x[a].size(); }
  std::size_t count() const { return size(0) * size(1) * size(2); }
  std::size_t index(std::size_t i, std::size_t j, std::size_t k) const {
    return (i * size(1) + j) * size(2) + k;
  }
};

// Centred: the cell centres of `cells`. Nodes: their corners, exactly min and max at the ends.
BoxGrid box_grid(const BoxGeometry& box, const Lattice& cells, BodySpec::Lattice lattice) {
  BoxGrid g;
  for (int a = 0; a < 3; ++a) {
    const Index n = cells.n[a];
    const double step = cells.step[a];
    if (lattice == BodySpec::Lattice::Centred) {
      for (Index k = 0; k < n; ++k) {
        g.x[a].push_back(cells.first[a] + k * step);
        g.w[a].push_back(step);
      }
      continue;
    }
    for (Index k = 0; k <= n; ++k) {
      g.x[a].push_back(std::lerp(box.min[a], box.max[a], static_cast<double>(k) / n));
      g.w[a].push_back(k == 0 || k == n ? 0.5 * step : step);
    }
  }
  return g;
}

void fill_box(ParticleSink& sink, const BoxGrid& g, double density) {
  sink.reserve(g.count());
  for (std::size_t i = 0; i < g.size(0); ++i)
    for (std::size_t j = 0; j < g.size(1); ++j)
      for (std::size_t k = 0; k < g.size(2); ++k)
        sink.add({g.x[0][i], g.x[1][j], g.x[2][k]}, density * (g.w[0][i] * g.w[1][j] * g.w[2][k]));
}

// The six faces of a box body whose particles start at index `first`.
void add_box_faces(Model& model, const std::string& body, std::size_t first, const BoxGrid& g) {
  static constexpr std::array<std::array<const char*, 2>, 3> names{
      {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}}};
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      ParticleFace face;
      face.normal[a] = side == 0 ? -1 : 1;
      // Index ranges [low, high) per direction: the whole grid but one layer along a.
      std::array<std::size_t, 3> low{0, 0, 0}, high{g.size(0), g.size(1), g.size(2)};
      low[a] = side == 0 ? 0 : g.size(a) - 1;
      high[a] = low[a] + 1;
      const auto area = [&](const std::array<std::size_t, 3>& at) {
        double product = 1;
        for (int d = 0; d < 3; ++d)
          if (d != a)
            product *= g.w[d][at[d]];
        return product;
      };
      for (std::size_t i = low[0]; i < high[0]; ++i)
        for (std::size_t j = low[1]; j < high[1]; ++j)
          for (std::size_t k = low[2]; k < high[2]; ++k) {
            face.particles.push_back(static_cast<Index>(first + g.index(i, j, k)));
            face.area.push_back(area({i, j, k}));
          }
      model.particle_faces[body + "/" + names[a][side]] = std::move(face);
    }
}

// Axis-aligned bounds of a cylinder: the base and top discs, each a disc of radius R about the
// unit axis a, reach R·sqrt(1 − a_i²) from their centres along axis i.
std::array<Vec3, 2> cylinder_bounds(const CylinderGeometry& g) {
  const Vec3 a = g.axis.normalized();
  const Vec3 top = g.base + g.axis;
  const Vec3 reach = g.radius * (1 - a.array().square()).max(0).sqrt().matrix();
  return {g.base.cwiseMin(top) - reach, g.base.cwiseMax(top) + reach};
}

// The range of s on the line (x, y, s) that can hold points of the cylinder, slightly widened,
// or false if it misses the cylinder. Used only to skip cells; each cell is then tested exactly.
bool column_range(const CylinderGeometry& g, double x, double y, double& s_low, double& s_high) {
  const double length = g.axis.norm();
  const Vec3 a = g.axis / length;
  const Vec3 q(x - g.base.x(), y - g.base.y(), -g.base.z()); // offset of (x, y, 0) from the base
  const double qa = q.dot(a);
  s_low = -std::numeric_limits<double>::infinity();
  s_high = std::numeric_limits<double>::infinity();
  // Axial: 0 ≤ qa + s·a_z ≤ L.
  if (std::abs(a.z()) > 1e-12) {
    const double s0 = -qa / a.z(), s1 = (length - qa) / a.z();
    s_low = std::min(s0, s1);
    s_high = std::max(s0, s1);
  }
  // Radial: r²(s) = A s² + B s + C < R², widened by a relative 1e-9.
  const double quad = 1 - a.z() * a.z();
  const double lin = 2 * (q.z() - a.z() * qa);
  const double r = g.radius * (1 + 1e-9);
  const double con = q.squaredNorm() - qa * qa - r * r;
  if (quad > 1e-12) {
    const double discriminant = lin * lin - 4 * quad * con;
    if (discriminant < 0)
      return false;
    const double root = std::sqrt(discriminant);
    s_low = std::max(s_low, (-lin - root) / (2 * quad));
    s_high = std::min(s_high, (-lin + root) / (2 * quad));
  }
  return s_low <= s_high;
}

void fill_cylinder(ParticleSink& sink, const CylinderGeometry& g, const Lattice& l) {
  const double length = g.axis.norm();
  const Vec3 a = g.axis / length;
  const double r2 = g.radius * g.radius;
  for (Index i = 0; i < l.n[0]; ++i)
    for (Index j = 0; j < l.n[1]; ++j) {
      const Vec3 bottom = l.centre(i, j, 0);
      double s_low = 0, s_high = 0;
      if (!column_range(g, bottom.x(), bottom.y(), s_low, s_high))
        continue;
      // Cells whose centres may lie in [s_low, s_high], one more each side.
      const double k_low = std::floor((s_low - l.first.z()) / l.step.z()) - 1;
      const double k_high = std::ceil((s_high - l.first.z()) / l.step.z()) + 1;
      const Index k0 = static_cast<Index>(std::clamp<double>(k_low, 0, l.n[2]));
      const Index k1 = static_cast<Index>(std::clamp<double>(k_high, -1, l.n[2] - 1));
      for (Index k = k0; k <= k1; ++k) {
        const Vec3 x = l.centre(i, j, k);
        const Vec3 d = x - g.base;
        const double t = d.dot(a);
        if (t >= 0 && t < length && (d - t * a).squaredNorm() < r2)
          sink.add(x);
      }
    }
}

// The lattice over the bounding box of the file's volumes; a particle in each cell one of the
// volumes encloses.
void fill_file(ParticleSink& sink, const std::filesystem::path& file, double spacing) {
  // Surface triangles as long as the spacing: the inscribed surface is at most Δp²/(8ρ) inside
  // the true one where its radius of curvature is ρ.
  const std::vector<Triangulation> volumes = solid_boundaries(file, spacing);
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const Triangulation& volume : volumes)
    for (const Vec3& x : volume.x) {
      low = low.cwiseMin(x);
      high = high.cwiseMax(x);
    }
  SPHFEM_CHECK(low.allFinite() && high.allFinite(), "the geometry file's volumes have no surface");
  check_fits(spacing, (high - low).minCoeff(), "its bounding box is");
  const Lattice l = covering_lattice(low, high, spacing);
  std::vector<char> enclosed(l.cell_count(), 0);
  for (const Triangulation& volume : volumes)
    mark_enclosed(volume, l, enclosed);
  std::size_t cell = 0;
  for (Index i = 0; i < l.n[0]; ++i)
    for (Index j = 0; j < l.n[1]; ++j)
      for (Index k = 0; k < l.n[2]; ++k)
        if (enclosed[cell++])
          sink.add(l.centre(i, j, k));
}

} // namespace

Lattice box_lattice(const BoxGeometry& box, double spacing) {
  const Vec3 size = box.max - box.min;
  std::array<double, 3> cells{};
  for (int a = 0; a < 3; ++a)
    cells[a] = std::max(1.0, std::round(size[a] / spacing));
  check_cell_count(cells, spacing);
  Lattice l;
  for (int a = 0; a < 3; ++a) {
    l.n[a] = static_cast<Index>(cells[a]);
    l.step[a] = size[a] / l.n[a];
    l.first[a] = box.min[a] + 0.5 * l.step[a];
  }
  return l;
}

Lattice covering_lattice(const Vec3& low, const Vec3& high, double spacing) {
  std::array<double, 3> cells{};
  for (int a = 0; a < 3; ++a) // a length within rounding of a multiple of Δp is that multiple
    cells[a] = std::max(1.0, std::ceil((high[a] - low[a]) / spacing - 1e-9));
  check_cell_count(cells, spacing);
  Lattice l;
  for (int a = 0; a < 3; ++a) {
    l.n[a] = static_cast<Index>(cells[a]);
    l.step[a] = spacing;
    l.first[a] = 0.5 * (low[a] + high[a]) - 0.5 * (l.n[a] - 1) * spacing;
  }
  return l;
}

void append_particles(Model& model, int body_id, const BodySpec& body, double density) {
  const double dp = body.spacing;
  SPHFEM_CHECK(dp > 0 && std::isfinite(dp), "spacing must be positive, got ", dp);
  SPHFEM_CHECK(body.h_factor > 0 && std::isfinite(body.h_factor), "h_factor must be positive, got ",
               body.h_factor);
  SPHFEM_CHECK(density > 0 && std::isfinite(density), "material density must be positive, got ",
               density);
  const double h = body.h_factor * dp;
  const GeometrySpec& g = body.geometry;
  SPHFEM_CHECK(body.lattice == BodySpec::Lattice::Centred || g.kind == GeometrySpec::Kind::Box,
               "lattice nodes is only possible for a box geometry");
  switch (g.kind) {
  case GeometrySpec::Kind::Box: {
    const Vec3 size = g.box.max - g.box.min;
    SPHFEM_CHECK(size.allFinite() && (size.array() > 0).all(),
                 "box max must exceed min in every direction");
    check_fits(dp, size.minCoeff(), "its smallest side is");
    const Lattice cells = box_lattice(g.box, dp);
    if (body.lattice == BodySpec::Lattice::Nodes) // one more point than cells per direction
      check_cell_count({cells.n[0] + 1.0, cells.n[1] + 1.0, cells.n[2] + 1.0}, dp);
    const BoxGrid grid = box_grid(g.box, cells, body.lattice);
    ParticleSink sink(model, body_id, 0, density, h);
    fill_box(sink, grid, density);
    add_box_faces(model, body.name, sink.first(), grid);
    return;
  }
  case GeometrySpec::Kind::Cylinder: {
    const CylinderGeometry& c = g.cylinder;
    SPHFEM_CHECK(c.radius > 0 && std::isfinite(c.radius), "cylinder radius must be positive");
    SPHFEM_CHECK(c.axis.allFinite() && c.axis.norm() > 0, "cylinder axis must be non-zero");
    SPHFEM_CHECK(c.base.allFinite(), "cylinder base must be finite");
    SPHFEM_CHECK(c.sector == Sector::Full,
                 "a quarter cylinder can only be meshed with hexahedra (method fem)");
    check_fits(dp, std::min(2 * c.radius, c.axis.norm()), "its smaller of diameter and length is");
    const auto [low, high] = cylinder_bounds(c);
    ParticleSink sink(model, body_id, dp * dp * dp, density, h);
    fill_cylinder(sink, c, covering_lattice(low, high, dp));
    SPHFEM_CHECK(sink.added() > 0, "no lattice point of spacing ", dp, " m lies inside the body");
    return;
  }
  case GeometrySpec::Kind::Ring:
    throw Error("a ring can only be meshed with hexahedra (method fem)");
  case GeometrySpec::Kind::File: {
    ParticleSink sink(model, body_id, dp * dp * dp, density, h);
    fill_file(sink, g.file, dp);
    SPHFEM_CHECK(sink.added() > 0, "no lattice point of spacing ", dp, " m lies inside the body");
    return;
  }
  }
  throw Error("unknown geometry kind");
}

} // namespace sphfem::mesher
