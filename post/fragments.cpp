#include "post/fragments.hpp"

#include "solver/core/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace sphfem::post {

namespace {

// Union–find with path halving; the root is the smallest index, so labels are deterministic.
struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b)
      parent[std::max(a, b)] = std::min(a, b);
  }
};

// Points binned in cubic cells of side `size`, sorted by cell: the points within `size` of a
// position lie in its cell and the 26 around it.
class CellList {
public:
  using Cell = std::array<long long, 3>;

  CellList(const std::vector<Vec3>& x, const std::vector<int>& indices, double size) : size_(size) {
    entries_.reserve(indices.size());
    for (int i : indices)
      entries_.emplace_back(cell(x[i]), i);
    std::sort(entries_.begin(), entries_.end());
  }

  template <class Visit> void near(const Vec3& x, Visit visit) const {
    const Cell c = cell(x);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const Cell key{c[0] + dx, c[1] + dy, c[2] + dz};
          auto it = std::lower_bound(entries_.begin(), entries_.end(), std::pair{key, -1});
          for (; it != entries_.end() && it->first == key; ++it)
            visit(it->second);
        }
  }

private:
  Cell cell(const Vec3& x) const {
    return {static_cast<long long>(std::floor(x.x() / size_)),
            static_cast<long long>(std::floor(x.y() / size_)),
            static_cast<long long>(std::floor(x.z() / size_))};
  }

  double size_;
  std::vector<std::pair<Cell, int>> entries_;
};

double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

void check_source(const FragmentSource& s) {
  const std::size_t P = s.x_p.size(), N = s.x_n.size(), E = s.hex_e.size();
  SPHFEM_CHECK(s.v_p.size() == P && s.m_p.size() == P &&
                   (s.killed_p.empty() || s.killed_p.size() == P),
               "fragments: ", P, " particle positions but ", s.v_p.size(), " velocities, ",
               s.m_p.size(), " masses and ", s.killed_p.size(), " kill flags");
  SPHFEM_CHECK(s.v_n.size() == N, "fragments: ", N, " node positions but ", s.v_n.size(),
               " velocities");
  SPHFEM_CHECK(s.m_e.size() == E && (s.eroded_e.empty() || s.eroded_e.size() == E),
               "fragments: ", E, " elements but ", s.m_e.size(), " masses and ", s.eroded_e.size(),
               " erosion flags");
  for (std::size_t k = 0; k < E; ++k)
    for (Index n : s.hex_e[k])
      SPHFEM_CHECK(n >= 0 && std::size_t(n) < N, "fragments: element ", k, " has node ", n, " of ",
                   N);
  for (const auto* x : {&s.x_p, &s.x_n})
    for (const Vec3& p : *x)
      SPHFEM_CHECK(p.allFinite(), "fragments: a position is not finite");
}

bool alive(const std::vector<char>& failed, std::size_t i) {
  return failed.empty() || !failed[i];
}

} // namespace

bool path_open(const std::vector<Vec3>& projectile, const FragmentSource& target,
               const FragmentSet& set, double rear, const Vec3& axis) {
  if (projectile.empty())
    return false;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& x : projectile)
    centre += x / double(projectile.size());
  const auto lateral = [&](const Vec3& x) {
    const Vec3 d = x - centre;
    return (d - d.dot(axis) * axis).norm();
  };
  double nose = -std::numeric_limits<double>::infinity(), radius = 0;
  for (const Vec3& x : projectile) {
    nose = std::max(nose, x.dot(axis));
    radius = std::max(radius, lateral(x));
  }
  if (nose <= rear)
    return false;
  const auto ahead = [&](const Vec3& x) { return x.dot(axis) > nose && lateral(x) < radius / 2; };
  for (std::size_t i = 0; i < target.x_p.size(); ++i)
    if (set.fragment_p[i] == 0 && ahead(target.x_p[i]))
      return false;
  for (std::size_t k = 0; k < target.hex_e.size(); ++k)
    if (set.fragment_e[k] == 0)
      for (Index n : target.hex_e[k])
        if (ahead(target.x_n[n]))
          return false;
  return true;
}

Vec3 lateral_direction(const Vec3& axis) {
  Eigen::Index k = 0;
  axis.cwiseAbs().minCoeff(&k);
  const Vec3 e = Vec3::Unit(k);
  return (e - e.dot(axis) * axis).normalized();
}

std::vector<Point2> convex_hull(std::vector<Point2> points) {
  auto less = [](const Point2& a, const Point2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  };
  std::sort(points.begin(), points.end(), less);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  const std::size_t n = points.size();
  if (n < 3)
    return points;
  std::vector<Point2> hull(2 * n);
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) { // lower hull
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0)
      --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = n - 1, lower = k + 1; i-- > 0;) { // upper hull
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0)
      --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1); // the last point is the first
  return hull;
}

double hull_diameter(const std::vector<Point2>& h) {
  const std::size_t n = h.size();
  if (n < 2)
    return 0;
  if (n == 2)
    return (h[1] - h[0]).norm();
  double best = 0;
  for (std::size_t i = 0, j = 1; i < n; ++i) {
    const std::size_t next = (i + 1) % n;
    // Advance j to the vertex farthest from edge (i, next): it and the edge are antipodal.
    while (cross(h[i], h[next], h[(j + 1) % n]) > cross(h[i], h[next], h[j]))
      j = (j + 1) % n;
    best = std::max({best, (h[i] - h[j]).norm(), (h[next] - h[j]).norm()});
  }
  return best;
}

std::vector<std::vector<Point2>> fragment_outlines(const FragmentSource& s, const FragmentSet& set,
                                                   const Vec3& e_x, const Vec3& e_y,
                                                   double spacing) {
  std::vector<std::vector<Point2>> points(set.fragments.size());
  const double half = spacing / 2;
  for (std::size_t i = 0; i < s.x_p.size(); ++i)
    if (const int f = set.fragment_p[i]; f >= 0) {
      const Point2 c(s.x_p[i].dot(e_x), s.x_p[i].dot(e_y));
      for (const Point2& corner :
           {Point2(-half, -half), Point2(half, -half), Point2(half, half), Point2(-half, half)})
        points[f].push_back(c + corner);
    }
  std::vector<char> taken(s.x_n.size(), 0); // a node belongs to one fragment: add it once
  for (std::size_t k = 0; k < s.hex_e.size(); ++k)
    if (const int f = set.fragment_e[k]; f >= 0)
      for (Index n : s.hex_e[k])
        if (!taken[n]) {
          taken[n] = 1;
          points[f].emplace_back(s.x_n[n].dot(e_x), s.x_n[n].dot(e_y));
        }
  std::vector<std::vector<Point2>> hulls;
  for (auto& p : points)
    hulls.push_back(convex_hull(std::move(p)));
  return hulls;
}

FragmentSet find_fragments(const FragmentSource& s, double reach, double spacing,
                           const Vec3& axis) {
  check_source(s);
  SPHFEM_CHECK(std::isfinite(reach) && reach >= 0, "fragments: connectivity distance ", reach,
               " m: expected a finite distance ≥ 0");
  const int P = int(s.x_p.size()), E = int(s.hex_e.size());
  UnionFind uf(P + E); // particles 0…P−1, then elements

  // Elements through shared nodes; owner[n] = an element using node n.
  std::vector<int> owner(s.x_n.size(), -1);
  for (int k = 0; k < E; ++k)
    if (alive(s.eroded_e, k))
      for (Index n : s.hex_e[k]) {
        if (owner[n] < 0)
          owner[n] = P + k;
        else
          uf.unite(owner[n], P + k);
      }

  std::vector<int> live_p;
  for (int i = 0; i < P; ++i)
    if (alive(s.killed_p, i))
      live_p.push_back(i);
  if (reach > 0 && !live_p.empty()) {
    const double r2 = reach * reach;
    const CellList particles(s.x_p, live_p, reach);
    for (int i : live_p)
      particles.near(s.x_p[i], [&](int j) {
        if (j > i && (s.x_p[j] - s.x_p[i]).squaredNorm() < r2)
          uf.unite(i, j);
      });
    std::vector<int> owned;
    for (std::size_t n = 0; n < owner.size(); ++n)
      if (owner[n] >= 0)
        owned.push_back(int(n));
    if (!owned.empty()) {
      const CellList nodes(s.x_n, owned, reach);
      for (int i : live_p)
        nodes.near(s.x_p[i], [&](int n) {
          if ((s.x_n[n] - s.x_p[i]).squaredNorm() < r2)
            uf.unite(i, owner[n]);
        });
    }
  }

  // Components in order of their first item, then sums per component.
  FragmentSet set;
  std::vector<int> component(P + E, -1), label(P + E, -1);
  std::vector<Fragment> found;
  std::vector<Vec3> momentum, moment;
  auto add = [&](int item, double m, const Vec3& x, const Vec3& v) -> Fragment& {
    const int root = uf.find(item);
    if (label[root] < 0) {
      label[root] = int(found.size());
      found.emplace_back();
      momentum.push_back(Vec3::Zero());
      moment.push_back(Vec3::Zero());
    }
    const int c = component[item] = label[root];
    found[c].mass += m;
    moment[c] += m * x;
    momentum[c] += m * v;
    return found[c];
  };
  for (int i = 0; i < P; ++i) {
    if (alive(s.killed_p, i)) {
      ++add(i, s.m_p[i], s.x_p[i], s.v_p[i]).particles;
    } else {
      ++set.debris_particles;
      set.debris_mass += s.m_p[i];
    }
  }
  for (int k = 0; k < E; ++k) {
    if (alive(s.eroded_e, k)) {
      Vec3 x = Vec3::Zero(), v = Vec3::Zero();
      for (Index n : s.hex_e[k]) {
        x += s.x_n[n] / 8;
        v += s.v_n[n] / 8;
      }
      ++add(P + k, s.m_e[k], x, v).elements;
    } else {
      ++set.debris_elements;
      set.debris_mass += s.m_e[k];
    }
  }
  for (std::size_t c = 0; c < found.size(); ++c)
    if (found[c].mass > 0) {
      found[c].com = moment[c] / found[c].mass;
      found[c].velocity = momentum[c] / found[c].mass;
    }

  // Most massive first.
  std::vector<int> order(found.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return found[a].mass > found[b].mass; });
  std::vector<int> rank(found.size());
  for (std::size_t r = 0; r < order.size(); ++r) {
    rank[order[r]] = int(r);
    set.fragments.push_back(found[order[r]]);
  }
  set.fragment_p.assign(P, -1);
  set.fragment_e.assign(E, -1);
  for (int i = 0; i < P + E; ++i)
    if (component[i] >= 0)
      (i < P ? set.fragment_p[i] : set.fragment_e[i - P]) = rank[component[i]];

  // Thickness along the axis; particles reach Δp/2 beyond their centres.
  const int F = int(set.fragments.size());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> lo(F, inf), hi(F, -inf);
  auto extend = [&](int f, double a, double half) {
    lo[f] = std::min(lo[f], a - half);
    hi[f] = std::max(hi[f], a + half);
  };
  for (int i = 0; i < P; ++i)
    if (set.fragment_p[i] >= 0)
      extend(set.fragment_p[i], s.x_p[i].dot(axis), spacing / 2);
  for (int k = 0; k < E; ++k)
    if (set.fragment_e[k] >= 0)
      for (Index n : s.hex_e[k])
        extend(set.fragment_e[k], s.x_n[n].dot(axis), 0);
  const Vec3 e1 = lateral_direction(axis), e2 = axis.cross(e1);
  const auto across = fragment_outlines(s, set, e1, e2, spacing);
  for (int f = 0; f < F; ++f) {
    set.fragments[f].thickness = hi[f] - lo[f];
    set.fragments[f].diameter = hull_diameter(across[f]);
  }
  return set;
}

int find_plug(const std::vector<Fragment>& fragments, const Vec3& axis, long long min_pieces) {
  for (std::size_t f = 1; f < fragments.size(); ++f)
    if (fragments[f].velocity.dot(axis) > 0 &&
        fragments[f].particles + fragments[f].elements >= min_pieces)
      return int(f);
  return -1;
}

} // namespace sphfem::post
