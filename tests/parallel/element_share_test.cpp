// What a rank of a distributed run holds of the elements' state (solver/state/hex_elements.hpp,
// Simulation): the state of the elements it computes and of the other ranks' elements at its
// nodes, and no other — counted by hand on a block cut in two — in the reference state. Built
// here in one process as rank 0 of two; that the run stays the single process's bit for bit
// with the state so held is tested by the mpirun runs of tests/e2e/mpi_launch_test.cpp.
#include "mesher/mesher.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/parallel/decomposition.hpp"
#include "solver/parallel/ranks.hpp"
#include "solver/time/cost_estimate.hpp"
#include "solver/time/simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace sphfem {
namespace {

// A 4 × 2 × 2 block of 1 mm Johnson–Cook hexahedra (a material point with a history).
const char* block = R"(
name: block
time: {end: 1.0e-6, output_interval: 1.0e-6}
materials:
  steel:
    model: johnson_cook
    density: 7850
    youngs_modulus: 200.0e9
    poisson_ratio: 0.3
    johnson_cook: {A: 2.0e8, B: 2.0e8, n: 0.5, C: 0, rate_form: power, reference_strain_rate: 1}
bodies:
  block:
    method: fem
    geometry: {box: {min: [0, 0, 0], max: [0.004, 0.002, 0.002]}}
    element_size: 0.001
    material: steel
)";

TEST(ElementShare, ARankHoldsTheStateOfItsElementsAndOfTheOthersAtItsNodesOnly) {
  if (!decomposition_available())
    GTEST_SKIP() << "built without MPI and Zoltan";
  if (ranks::size() != 1)
    GTEST_SKIP() << "builds rank 0's share in one process";
  const Case c = read_case_text(block, "block.yaml");
  const Model m = mesh_case(c);
  ASSERT_EQ(m.element_count(), 16);
  const Decomposition d = decompose(m, entity_costs(m), 2);
  // Cut at x = 2 mm (8 elements a part); the 9 nodes on the cut go to the lower part, so it
  // also holds the 4 upper elements at the cut: 12 of the 16 elements' state, the upper 8.
  Index lower = 0;
  for (Index k = 0; k < m.element_count(); ++k)
    if (m.x_n[m.hex_e[k][0]].x() < 1e-3)
      lower = k;
  const bool rank0_is_lower = d.part_e[lower] == 0;
  const std::size_t held = rank0_is_lower ? 12 : 8;

  const Simulation whole(c, m);
  const Simulation share(c, m, &d);
  const HexElements& w = whole.elements();
  HexElements e = share.elements();
  EXPECT_TRUE(w.slot_e.empty());
  EXPECT_EQ(w.V_e.size(), 16u);
  ASSERT_EQ(e.slot_e.size(), 16u);
  e.for_each_state_field(
      [&](const char* name, auto& field) { EXPECT_EQ(field.size(), held) << name; });
  std::size_t slots = 0;
  for (Index k = 0; k < m.element_count(); ++k) {
    const bool computed = d.part_e[k] == 0;
    const bool at_the_cut = std::ranges::any_of(
        m.hex_e[k], [&](Index i) { return std::abs(m.x_n[i].x() - 2e-3) < 1e-9; });
    const bool holds = computed || (rank0_is_lower && at_the_cut);
    EXPECT_EQ(e.slot_e[k] >= 0, holds) << "element " << k;
    if (e.slot_e[k] < 0)
      continue;
    ++slots;
    const Index s = e.slot_e[k];
    ASSERT_LT(static_cast<std::size_t>(s), held);
    // The elements it computes come first (HexElements' slots), and each slot holds its
    // element's reference state, as one process does.
    EXPECT_EQ(static_cast<std::size_t>(s) < 8u, computed) << "element " << k;
    EXPECT_EQ(e.V_e[s], w.V_e[k]);
    EXPECT_EQ(e.V_e[s], e.V0_e[k]);
    EXPECT_EQ(e.point_e[s].plastic_strain, w.point_e[k].plastic_strain);
    EXPECT_EQ(e.point_e[s].temperature, w.point_e[k].temperature);
    EXPECT_EQ(e.S_e[s], w.S_e[k]);
  }
  EXPECT_EQ(slots, held);
}

} // namespace
} // namespace sphfem
