// Test helper: a Simulation built from case text through the product's own reader and mesher.
#pragma once

#include "mesher/mesher.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/time/probes.hpp"
#include "solver/time/simulation.hpp"

#include <string>

namespace sphfem::test {

struct FemCase {
  Case spec;
  Model model;
  Simulation sim;
  std::vector<Probe> probes;

  explicit FemCase(const std::string& yaml)
      : spec(read_case_text(yaml, "test.yaml")), model(mesh_case(spec)), sim(spec, model),
        probes(locate_probes(spec, model)) {}

  // Steps to the case's end time, calling record() after every step.
  template <class Record> void run(Record record) {
    while (sim.time() < spec.time.end * (1 - 1e-12)) {
      sim.step(std::min(sim.stable_dt(), spec.time.end - sim.time()));
      record();
    }
  }
};

} // namespace sphfem::test
