// Fragments and the plug (post/fragments.hpp, post/plug.hpp): on synthetic particle lattices
// and hexahedra, the components, their sums and sizes are exact; the cell-list search equals a
// brute-force one; and `sphfem post plug` on a tiny perforation run accounts for the plate's
// whole mass, draws its picture and rejects an unknown body without writing anything, and on
// run folders with a missing or bad file (model.h5, the frames) fails with one line naming it.
#include "png_pixels.hpp"
#include "tests/support/command.hpp"

#include "post/fragments.hpp"
#include "post/plug.hpp"
#include "solver/io/model_h5.hpp"
#include "tests/support/punch_case.hpp"

#include <nlohmann/json.hpp>
#include <vtkCellType.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <sstream>

#include <unistd.h>

namespace fs = std::filesystem;
using sphfem::test::Result;
using sphfem::test::run_sphfem;
using sphfem::test::slurp;
using namespace sphfem;
using namespace sphfem::post;

namespace {

constexpr double dp = 1e-3; // lattice spacing, m

// An nx × ny × nz lattice of spacing dp from `corner`, with varied masses and velocities.
void add_lattice(FragmentSource& s, Vec3 corner, int nx, int ny, int nz, Vec3 velocity) {
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double n = double(s.x_p.size());
        s.x_p.push_back(corner + dp * Vec3(i, j, k));
        s.v_p.push_back(velocity + Vec3(0.1 * i, -0.2 * j, 0.3 * std::sin(n)));
        s.m_p.push_back(7.85e-6 * (1 + 0.01 * std::cos(n)));
        s.killed_p.push_back(0);
      }
}

// Expected sums over particles [first, last) that are alive.
Fragment sums(const FragmentSource& s, std::size_t first, std::size_t last) {
  Fragment f;
  Vec3 mx = Vec3::Zero(), mv = Vec3::Zero();
  for (std::size_t i = first; i < last; ++i)
    if (!s.killed_p[i]) {
      f.mass += s.m_p[i];
      mx += s.m_p[i] * s.x_p[i];
      mv += s.m_p[i] * s.v_p[i];
      ++f.particles;
    }
  f.com = mx / f.mass;
  f.velocity = mv / f.mass;
  return f;
}

// Sums in a different order than the code's: agree to round-off.
void expect_same(const Fragment& a, const Fragment& b) {
  EXPECT_NEAR(a.mass, b.mass, 1e-14 * b.mass);
  EXPECT_NEAR((a.com - b.com).norm(), 0, 1e-15);
  EXPECT_NEAR((a.velocity - b.velocity).norm(), 0, 1e-12);
  EXPECT_EQ(a.particles, b.particles);
}

const Vec3 down = -Vec3::UnitZ(); // impact axis: a projectile moving along −z

// One unit hexahedron of side `a` at `corner` (gmsh order), its nodes appended.
void add_hex(FragmentSource& s, Vec3 corner, double a, double mass, Vec3 velocity) {
  const Index n0 = Index(s.x_n.size());
  const double c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  Hex hex;
  for (int a_ = 0; a_ < 8; ++a_) {
    s.x_n.push_back(corner + a * Vec3(c[a_][0], c[a_][1], c[a_][2]));
    s.v_n.push_back(velocity);
    hex[a_] = n0 + a_;
  }
  s.hex_e.push_back(hex);
  s.m_e.push_back(mass);
  s.eroded_e.push_back(0);
}

} // namespace

TEST(Fragments, SeparatedCloudsAreTwoFragmentsWithExactSumsTouchingCloudsOne) {
  for (const double gap : {3.0, 1.0}) { // in spacings, between the clouds' facing layers
    FragmentSource s;
    add_lattice(s, Vec3::Zero(), 6, 6, 3, Vec3(0, 0, -10)); // the plate
    const std::size_t split = s.x_p.size();
    add_lattice(s, Vec3((5 + gap) * dp, 0, 0), 3, 3, 3, Vec3(1, 0, -300)); // a faster piece
    const auto set = find_fragments(s, 1.5 * dp, dp, down);
    if (gap > 1.5) {
      ASSERT_EQ(set.fragments.size(), 2u);
      expect_same(set.fragments[0], sums(s, 0, split));
      expect_same(set.fragments[1], sums(s, split, s.x_p.size()));
      EXPECT_EQ(find_plug(set.fragments, down), 1);
      EXPECT_EQ(find_plug(set.fragments, -down), -1);    // it moves against that axis
      EXPECT_EQ(find_plug(set.fragments, down, 28), -1); // 27 particles: below 28 no plug
      EXPECT_EQ(set.fragment_p[0], 0);
      EXPECT_EQ(set.fragment_p[split], 1);
    } else {
      ASSERT_EQ(set.fragments.size(), 1u);
      expect_same(set.fragments[0], sums(s, 0, s.x_p.size()));
      EXPECT_EQ(find_plug(set.fragments, down), -1); // the main fragment is never the plug
    }
    EXPECT_EQ(set.debris_particles, 0);
    EXPECT_EQ(set.debris_mass, 0.0);
  }
}

TEST(Fragments, KilledParticlesAreDebrisAndAChainConnectsWithinReachOnly) {
  FragmentSource s;
  add_lattice(s, Vec3::Zero(), 5, 5, 2, Vec3(0, 0, -50));
  double killed_mass = 0;
  for (std::size_t i = 0; i < s.x_p.size(); i += 7) {
    s.killed_p[i] = 1;
    killed_mass += s.m_p[i];
  }
  auto set = find_fragments(s, 1.5 * dp, dp, down);
  ASSERT_EQ(set.fragments.size(), 1u);
  expect_same(set.fragments[0], sums(s, 0, s.x_p.size()));
  EXPECT_EQ(set.debris_particles, 8);
  EXPECT_NEAR(set.debris_mass, killed_mass, 1e-15 * killed_mass);
  EXPECT_EQ(set.fragment_p[0], -1);

  // Killing the middle layer of a slab splits it.
  FragmentSource slab;
  add_lattice(slab, Vec3::Zero(), 4, 4, 3, Vec3::Zero());
  for (std::size_t i = 16; i < 32; ++i)
    slab.killed_p[i] = 1;
  EXPECT_EQ(find_fragments(slab, 1.5 * dp, dp, down).fragments.size(), 2u);

  FragmentSource chain; // 8 particles in a line, 1.4 spacings apart
  for (int i = 0; i < 8; ++i) {
    chain.x_p.push_back(Vec3(1.4 * dp * i, 0.2 * dp, -0.3 * dp));
    chain.v_p.push_back(Vec3::Zero());
    chain.m_p.push_back(1e-6);
  }
  EXPECT_EQ(find_fragments(chain, 1.5 * dp, dp, down).fragments.size(), 1u);
  EXPECT_EQ(find_fragments(chain, 1.2 * dp, dp, down).fragments.size(), 8u);
}

TEST(Fragments, CellListSearchEqualsBruteForce) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  FragmentSource s;
  for (int i = 0; i < 400; ++i) {
    s.x_p.push_back(Vec3(u(random), u(random), 0.2 * u(random)));
    s.v_p.push_back(Vec3::Zero());
    s.m_p.push_back(1e-6);
  }
  const double reach = 1.5 * dp;
  const auto set = find_fragments(s, reach, dp, down);
  // Brute force: label propagation over all pairs until nothing changes.
  std::vector<int> label(s.x_p.size());
  std::iota(label.begin(), label.end(), 0);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < s.x_p.size(); ++i)
      for (std::size_t j = 0; j < s.x_p.size(); ++j)
        if ((s.x_p[i] - s.x_p[j]).norm() < reach && label[j] < label[i]) {
          label[i] = label[j];
          changed = true;
        }
  }
  for (std::size_t i = 0; i < s.x_p.size(); ++i)
    for (std::size_t j = 0; j < s.x_p.size(); ++j)
      EXPECT_EQ(label[i] == label[j], set.fragment_p[i] == set.fragment_p[j]) << i << " " << j;
  EXPECT_GT(set.fragments.size(), 5u); // a mix of clusters, not one blob or all singles
  EXPECT_LT(set.fragments.size(), 300u);
}

TEST(Fragments, ElementsJoinThroughSharedNodesAndParticlesWithinReach) {
  FragmentSource s;
  add_hex(s, Vec3::Zero(), dp, 2e-6, Vec3(0, 0, -1));
  add_hex(s, Vec3(dp, 0, 0), dp, 2e-6, Vec3(0, 0, -1));
  // Let the second hexahedron use the first one's +x face nodes: they share four nodes.
  for (int a : {0, 3, 4, 7})
    s.hex_e[1][a] = s.hex_e[0][a == 0 ? 1 : a == 3 ? 2 : a == 4 ? 5 : 6];
  add_hex(s, Vec3(5 * dp, 0, 0), dp, 3e-6, Vec3(0, 0, -200)); // apart
  s.eroded_e.assign(3, 0);
  auto set = find_fragments(s, 1.5 * dp, dp, down);
  ASSERT_EQ(set.fragments.size(), 2u);
  EXPECT_EQ(set.fragments[0].elements, 2);
  EXPECT_NEAR(set.fragments[0].mass, 4e-6, 1e-20);
  EXPECT_EQ(set.fragments[1].elements, 1);
  // An element's mass sits at its centroid, with its nodes' mean velocity.
  EXPECT_NEAR((set.fragments[1].com - Vec3(5.5 * dp, 0.5 * dp, 0.5 * dp)).norm(), 0, 1e-15);
  EXPECT_NEAR(set.fragments[1].velocity.z(), -200, 1e-12);
  EXPECT_EQ(find_plug(set.fragments, down, 1), 1);
  EXPECT_EQ(find_plug(set.fragments, down), -1); // one element is not a plug of 27 pieces

  // A particle 1.2 spacings beyond the lone hexahedron's node joins it; one 2 spacings off does
  // not.
  for (const double x : {7.2 * dp, 8.0 * dp}) {
    FragmentSource t = s;
    t.x_p = {Vec3(x, 0, 0)};
    t.v_p = {Vec3(0, 0, -100)};
    t.m_p = {1e-6};
    const bool joins = x < 7.5 * dp;
    const auto with = find_fragments(t, 1.5 * dp, dp, down);
    ASSERT_EQ(with.fragments.size(), joins ? 2u : 3u) << x;
    EXPECT_EQ(with.fragment_p[0] == with.fragment_e[2], joins) << x;
    EXPECT_EQ(with.fragments[with.fragment_e[2]].particles, joins ? 1 : 0) << x;
  }

  // An eroded element is debris and no longer bridges its neighbours.
  s.eroded_e[0] = 1;
  set = find_fragments(s, 1.5 * dp, dp, down);
  EXPECT_EQ(set.debris_elements, 1);
  EXPECT_NEAR(set.debris_mass, 2e-6, 1e-20);
  EXPECT_EQ(set.fragments.size(), 2u);
}

TEST(Fragments, BlockSizesAreItsThicknessAndDiagonal) {
  // Particles stand for cubes of side Δp, so a 10 × 10 × 4 lattice measures 10 × 10 × 4 Δp.
  FragmentSource s;
  add_lattice(s, Vec3(0.01, -0.003, 0.002), 10, 10, 4, Vec3(0, 0, -100));
  const auto set = find_fragments(s, 1.5 * dp, dp, down);
  ASSERT_EQ(set.fragments.size(), 1u);
  // Exact here; the brief allows one spacing for deformed fragments.
  EXPECT_NEAR(set.fragments[0].thickness, 4 * dp, 1e-12);
  EXPECT_NEAR(set.fragments[0].diameter, 10 * std::sqrt(2.0) * dp, 1e-12);
  // Along x the "thickness" is the block's x extent.
  const auto along_x = find_fragments(s, 1.5 * dp, dp, Vec3::UnitX());
  EXPECT_NEAR(along_x.fragments[0].thickness, 10 * dp, 1e-12);
  EXPECT_NEAR(along_x.fragments[0].diameter, std::hypot(10, 4) * dp, 1e-12);

  // A hexahedron's nodes are its extent.
  FragmentSource h;
  add_hex(h, Vec3(0, 0, 0), 2 * dp, 1e-6, Vec3::Zero());
  const auto hex = find_fragments(h, 0, 0, down);
  EXPECT_NEAR(hex.fragments[0].thickness, 2 * dp, 1e-15);
  EXPECT_NEAR(hex.fragments[0].diameter, 2 * std::sqrt(2.0) * dp, 1e-15);
}

TEST(Fragments, ConvexHullAndDiameter) {
  std::vector<Point2> points;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 2; ++j)
      points.emplace_back(i, j); // a 4 × 2 grid: hull = its 4 corners
  const auto hull = convex_hull(points);
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_NEAR(hull_diameter(hull), std::hypot(4, 2), 1e-14);
  std::vector<Point2> polygon;
  for (int k = 0; k < 7; ++k) // regular heptagon of radius 1: diameter 2 sin(3π/7)
    polygon.emplace_back(std::cos(2 * M_PI * k / 7), std::sin(2 * M_PI * k / 7));
  EXPECT_NEAR(hull_diameter(convex_hull(polygon)), 2 * std::sin(3 * M_PI / 7), 1e-14);
  EXPECT_EQ(convex_hull({Point2(1, 1), Point2(1, 1)}).size(), 1u);
  EXPECT_EQ(hull_diameter({Point2(0, 0)}), 0.0);
}

// A plate of particles 10 × 10 × 4 mm (rear face z = −4 mm) with a 5 × 5 mm hole under a
// 4 × 4 mm projectile (radius 2.8 mm about its axis): the path is open when the nose is beyond the
// rear face and nothing of the main fragment lies ahead of it within 1.4 mm of the axis — a plug
// hanging on the plate by a column of particles blocks it, the same plug cut loose does not.
TEST(Fragments, APathIsOpenWhenTheNoseIsThroughAndNoMainFragmentIsAhead) {
  const auto particle = [](FragmentSource& s, Vec3 x) {
    s.x_p.push_back(x);
    s.v_p.push_back(Vec3::Zero());
    s.m_p.push_back(7.85e-6);
    s.killed_p.push_back(0);
  };
  FragmentSource ring;
  for (int k = 1; k <= 4; ++k)
    for (int j = -5; j <= 5; ++j)
      for (int i = -5; i <= 5; ++i)
        if (std::abs(i) > 2 || std::abs(j) > 2)
          particle(ring, dp * Vec3(i, j, -k));
  const double rear = 4 * dp; // the largest x · (−z) of the plate
  const auto projectile = [](double nose_z) {
    std::vector<Vec3> points;
    for (int k = 0; k <= 10; ++k)
      for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i)
          points.push_back(dp * Vec3(i, j, nose_z / dp + k));
    return points;
  };
  const auto open = [&](const FragmentSource& target, double nose_z) {
    return path_open(projectile(nose_z), target, find_fragments(target, 1.5 * dp, dp, down), rear,
                     down);
  };
  EXPECT_FALSE(open(ring, -3 * dp));  // the nose still in the hole
  EXPECT_TRUE(open(ring, -4.5 * dp)); // through, the hole empty
  EXPECT_FALSE(open(ring, 10 * dp));  // before impact
  EXPECT_FALSE(path_open({}, ring, find_fragments(ring, 1.5 * dp, dp, down), rear, down));

  FragmentSource loose = ring; // a 5 × 5 × 4 plug 1 mm ahead of the nose
  for (int k = 0; k < 4; ++k)
    for (int j = -2; j <= 2; ++j)
      for (int i = -2; i <= 2; ++i)
        particle(loose, dp * Vec3(i, j, -6 - k));
  EXPECT_TRUE(open(loose, -5 * dp));
  FragmentSource hanging = loose; // the plug joined to the ring by a column at x = 3 mm
  for (int k = 5; k <= 6; ++k)
    particle(hanging, dp * Vec3(3, 0, -k));
  ASSERT_EQ(find_fragments(hanging, 1.5 * dp, dp, down).fragments.size(), 1u);
  EXPECT_FALSE(open(hanging, -5 * dp));
  EXPECT_TRUE(open(hanging, -10 * dp)); // the nose beyond the plug: nothing ahead
}

// ---- the command on a real run ----

TEST(PostPlug, OnATinyPerforationRunAccountsForThePlateMass) {
  const fs::path dir = fs::temp_directory_path() / ("sphfem_plug_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "case.yaml") << test::punch_case(0.009, 0.004, 0.008);
  const fs::path out = dir / "out";
  auto r = run_sphfem("run " + (dir / "case.yaml").string() + " -o " + out.string() + " -q", dir);
  ASSERT_EQ(r.code, 0) << r.err;

  r = run_sphfem("post plug " + out.string() + " --size 800x500", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("plug"), std::string::npos) << r.out;
  const fs::path post = out / "post";
  ASSERT_TRUE(fs::exists(post / "plug.json"));
  ASSERT_TRUE(fs::exists(post / "fragments.csv"));
  ASSERT_TRUE(fs::exists(post / "plug.png"));
  const auto j = nlohmann::json::parse(slurp(post / "plug.json"));
  EXPECT_EQ(j["body"], "plate");
  EXPECT_NEAR(j["time_s"].get<double>(), 1.5e-5, 1e-9);
  // The projectile moves along −z: that is the impact axis.
  EXPECT_NEAR(j["impact_axis"][2].get<double>(), -1, 1e-9);
  EXPECT_NEAR(j["connect_distance_m"].get<double>(), 1.5e-3, 1e-15);
  double total = j["debris"]["mass_kg"].get<double>();
  long long particles = j["debris"]["particles"].get<long long>();
  for (const auto& f : j["fragments"]) {
    total += f["mass_kg"].get<double>();
    particles += f["particles"].get<long long>();
  }
  const double plate = 7850 * 0.018 * 0.018 * 0.004;
  EXPECT_NEAR(total, plate, 1e-9 * plate);
  EXPECT_EQ(particles, 18 * 18 * 4);
  EXPECT_EQ(j["main"], 0);
  if (!j["plug"].is_null()) { // moving with the projectile
    EXPECT_GT(j["fragments"][j["plug"].get<int>()]["axial_velocity_m_per_s"].get<double>(), 0);
  }
  // One CSV row per fragment under a header.
  const std::string csv = slurp(post / "fragments.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + long(j["fragments"].size()));
  const auto png = sphfem_test::read_png(post / "plug.png");
  EXPECT_EQ(png.width, 800);
  EXPECT_EQ(png.height, 500);
  EXPECT_GT(png.non_white_fraction(), 0.01);

  // --time picks the nearest frame (frames fall on the first step past each output time).
  r = run_sphfem("post plug " + out.string() + " --time 4e-6 -o " + (dir / "early").string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(slurp(dir / "early" / "plug.json"))["time_s"].get<double>(),
              5e-6, 0.1e-6);

  // The projectile as the target: hexahedra only, element masses ρ V back to round-off, and
  // +z for the impact axis, as the plate had no momentum at t = 0.
  r = run_sphfem("post plug " + out.string() + " --body projectile -o " + (dir / "hexes").string(),
                 dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto hexes = nlohmann::json::parse(slurp(dir / "hexes" / "plug.json"));
  ASSERT_EQ(hexes["fragments"].size(), 1u);
  EXPECT_EQ(hexes["fragments"][0]["elements"], 8 * 8 * 8);
  const double projectile = 7838 * 0.008 * 0.008 * 0.008;
  EXPECT_NEAR(hexes["fragments"][0]["mass_kg"].get<double>(), projectile, 1e-9 * projectile);
  EXPECT_NEAR(hexes["impact_axis"][2].get<double>(), 1, 1e-15);
  EXPECT_EQ(hexes["impact_axis_from"].get<std::string>().rfind("+z", 0), 0u);

  // Bad input: one line naming the problem, nothing written.
  r = run_sphfem("post plug " + out.string() + " --body wall -o " + (dir / "bad").string(), dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--body wall: no such body"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("plate, projectile"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  r = run_sphfem("post plug " + dir.string() + " -o " + (dir / "bad").string(), dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("no results.pvd"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  if (!HasFailure())
    fs::remove_all(dir);
}

// A 4 × 4 × 16 mm block at 3000 m/s through the 4 mm plate: by 15 µs it lies wholly below the
// plate's rear face (z = −4 mm at t = 0), so the plate is perforated whether or not a plug is
// counted — here none is (--min-pieces above the plate's particle count), as when a target shatters
// into debris. In the first frame the block is above the plate: not through.
TEST(PostPlug, AProjectileBeyondTheRearFaceHasPerforatedWithoutAPlug) {
  const fs::path dir =
      fs::temp_directory_path() / ("sphfem_plug_through_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "case.yaml") << test::punch_case(0.004, 0.002, 0.016);
  const fs::path out = dir / "out";
  auto r = run_sphfem("run " + (dir / "case.yaml").string() + " -o " + out.string() +
                          " -q --set 'bodies.projectile.velocity=[0,0,-3000]'",
                      dir);
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_sphfem("post plug " + out.string() + " --min-pieces 100000 -o " + (dir / "late").string(),
                 dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto late = nlohmann::json::parse(slurp(dir / "late" / "plug.json"));
  EXPECT_TRUE(late["plug"].is_null());
  EXPECT_TRUE(late["projectile_passed_through"].get<bool>());
  EXPECT_NE(r.out.find("perforated"), std::string::npos) << r.out;
  r = run_sphfem("post plug " + out.string() + " --time 0 -o " + (dir / "first").string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto first = nlohmann::json::parse(slurp(dir / "first" / "plug.json"));
  EXPECT_FALSE(first["projectile_passed_through"].get<bool>());
  if (!HasFailure())
    fs::remove_all(dir);
}

// A target that flies freely (no force reaches it: the block rests 3 mm away and the plate moves
// off at 5 m/s) travels v·t: its centre of mass's displacement since the first frame, from
// kinematics alone. The impact axis is +z (the other body has no momentum), so travel < 0.
TEST(PostPlug, AFreeTargetTravelsItsVelocityTimesTime) {
  test::Scratch scratch("plug_travel");
  const fs::path& dir = scratch.dir;
  std::ofstream(dir / "case.yaml") << test::punch_case(0.004, 0.002, 0.004);
  const fs::path out = dir / "out";
  auto r = run_sphfem("run " + (dir / "case.yaml").string() + " -o " + out.string() +
                          " -q --set 'bodies.projectile.velocity=[0,0,0]' --set "
                          "'bodies.plate.velocity=[0,0,-5]'",
                      dir);
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_sphfem("post plug " + out.string() + " -o " + (dir / "post").string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(dir / "post" / "plug.json"));
  ASSERT_EQ(j["fragments"].size(), 1u);
  const double t = j["time_s"].get<double>(), travel = j["fragments"][0]["travel_m"].get<double>();
  std::printf("free plate: travel %.6g m after %.4g s (v t = %.6g m)\n", travel, t, -5 * t);
  EXPECT_NEAR(travel, -5 * t, 1e-3 * 5 * t);
  EXPECT_NE(slurp(dir / "post" / "fragments.csv").find(",travel [m]\n"), std::string::npos);
}

TEST(PostPlug, SeveralParticleBodiesNeedBody) {
  const fs::path dir =
      fs::temp_directory_path() / ("sphfem_plug_bodies_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  Model m; // two particle bodies of one particle each
  m.body_names = {"left", "right"};
  m.spacing_b = {dp, dp};
  m.x_p = {Vec3::Zero(), Vec3(0.01, 0, 0)};
  m.m_p = {1e-6, 1e-6};
  m.rho_p = {1000, 1000};
  m.h_p = {1.2 * dp, 1.2 * dp};
  m.body_p = {0, 1};
  write_model_h5(m, dir / "model.h5");
  std::ofstream(dir / "results.pvd") << "<VTKFile type=\"Collection\"><Collection>\n"
                                     << "</Collection></VTKFile>\n";
  const auto r = run_sphfem("post plug " + dir.string(), dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("several bodies have particles (left, right); choose the target with "
                       "--body"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "post"));
  if (!HasFailure())
    fs::remove_all(dir);
}

namespace {

// A data array of a frame file: its name, components, values as text, and where it lives.
struct VtuArray {
  std::string name;
  int components;
  std::string values;
  bool on_cells = false;
};

// A frame file in VTK's ASCII XML: `points` points 1 mm apart along x, one vertex per point
// (cell_type VTK_VERTEX) or one cell of `cell_type` over all of them, and `arrays`.
void write_vtu(const fs::path& file, int points, int cell_type,
               const std::vector<VtuArray>& arrays) {
  const bool vertices = cell_type == VTK_VERTEX;
  std::ostringstream xyz, connectivity, offsets, types, point_data, cell_data;
  for (int i = 0; i < points; ++i) {
    xyz << i * 1e-3 << " 0 0 ";
    connectivity << i << " ";
    if (vertices) {
      offsets << i + 1 << " ";
      types << VTK_VERTEX << " ";
    }
  }
  if (!vertices) {
    offsets << points;
    types << cell_type;
  }
  for (const VtuArray& a : arrays)
    (a.on_cells ? cell_data : point_data)
        << "<DataArray type=\"Float64\" Name=\"" << a.name << "\" NumberOfComponents=\""
        << a.components << "\" format=\"ascii\">" << a.values << "</DataArray>\n";
  const auto array = [](const char* type, const char* name, const std::ostringstream& values) {
    return std::string("<DataArray type=\"") + type + "\" Name=\"" + name + "\" format=\"ascii\">" +
           values.str() + "</DataArray>\n";
  };
  fs::create_directories(file.parent_path());
  std::ofstream(file) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" "
                         "version=\"0.1\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
                      << points << "\" NumberOfCells=\"" << (vertices ? points : 1) << "\">\n"
                      << "<PointData>\n"
                      << point_data.str() << "</PointData>\n<CellData>\n"
                      << cell_data.str() << "</CellData>\n<Points><DataArray type=\"Float64\" "
                      << "NumberOfComponents=\"3\" format=\"ascii\">" << xyz.str()
                      << "</DataArray></Points>\n<Cells>\n"
                      << array("Int64", "connectivity", connectivity)
                      << array("Int64", "offsets", offsets) << array("UInt8", "types", types)
                      << "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

// results.pvd of one frame at t = 0 with the particle file and, if `fe`, an FE file.
void write_one_frame_pvd(const fs::path& run, bool fe) {
  std::ofstream(run / "results.pvd")
      << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
      << "<Collection>\n<DataSet timestep=\"0\" part=\"0\" file=\"frames/sph_000000.vtu\"/>\n"
      << (fe ? "<DataSet timestep=\"0\" part=\"1\" file=\"frames/fe_000000.vtu\"/>\n" : "")
      << "</Collection>\n</VTKFile>\n";
}

// model.h5 of a plate of one particle and a body "ghost" with nothing in it.
void write_plate_model(const fs::path& run) {
  Model m;
  m.body_names = {"plate", "ghost"};
  m.spacing_b = {dp, 0};
  m.x_p = {Vec3::Zero()};
  m.m_p = {1e-6};
  m.rho_p = {7850};
  m.h_p = {1.2 * dp};
  m.body_p = {0};
  write_model_h5(m, run / "model.h5");
}

} // namespace

// A run folder with a file missing or wrong in one way: `post plug` fails with one line naming
// the file and the fault, and writes nothing. The same folder with good files gives a result, so
// each fault alone is the cause.
TEST(PostPlug, BadRunFilesAreOneLineErrors) {
  test::Scratch scratch("plug_bad_files");
  const fs::path& dir = scratch.dir;
  const VtuArray velocity{"velocity", 3, "0 0 0"}, mass{"mass", 1, "1e-6"}, body{"body_id", 1, "0"};
  // One folder per case: the plate model, one frame, the particle file given.
  const auto folder = [&](const std::string& name, const std::vector<VtuArray>& particle) {
    const fs::path run = dir / name;
    fs::create_directories(run);
    write_plate_model(run);
    write_one_frame_pvd(run, false);
    write_vtu(run / "frames" / "sph_000000.vtu", 1, VTK_VERTEX, particle);
    return run;
  };
  const fs::path good = folder("good", {velocity, mass, body});
  const Result ok = run_sphfem("post plug " + good.string(), dir);
  ASSERT_EQ(ok.code, 0) << ok.err;
  ASSERT_TRUE(fs::exists(good / "post" / "plug.json"));

  std::vector<std::pair<std::string, std::string>> cases; // arguments, message
  cases.push_back({(dir / "missing").string(), "missing: no such run folder"});
  fs::create_directories(dir / "no_model");
  write_one_frame_pvd(dir / "no_model", false);
  cases.push_back({(dir / "no_model").string(), "no_model: no model.h5"});
  const fs::path no_particles = folder("no_particles", {velocity, mass, body});
  Model empty;
  empty.body_names = {"plate"};
  write_model_h5(empty, no_particles / "model.h5");
  cases.push_back({no_particles.string(), "model.h5: no body has particles; choose the target "
                                          "with --body (bodies: plate)"});
  cases.push_back({good.string() + " --body ghost", "--body ghost: has neither particles nor "
                                                    "elements"});
  cases.push_back(
      {folder("no_velocity", {mass, body}).string(), "sph_000000.vtu: no velocity array"});
  cases.push_back({folder("wide_mass", {velocity, {"mass", 3, "1 2 3"}, body}).string(),
                   "sph_000000.vtu: array mass has 1×3 values, expected 1×1"});
  cases.push_back({folder("other_body", {velocity, mass, {"body_id", 1, "1"}}).string(),
                   "sph_000000.vtu: no particles or elements of body plate"});
  const fs::path tetra = folder("tetra", {velocity, mass, body});
  write_one_frame_pvd(tetra, true);
  write_vtu(tetra / "frames" / "fe_000000.vtu", 4, VTK_TETRA,
            {{"velocity", 3, "0 0 0 0 0 0 0 0 0 0 0 0"},
             {"density", 1, "7850", true},
             {"body_id", 1, "0", true}});
  cases.push_back({tetra.string(), "fe_000000.vtu: cell 0 is not a hexahedron"});
  for (const auto& [args, message] : cases) {
    const fs::path out = dir / "out";
    const Result r = run_sphfem("post plug " + args + " -o " + out.string(), dir);
    EXPECT_NE(r.code, 0) << args;
    EXPECT_EQ(r.err.rfind("sphfem: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}
