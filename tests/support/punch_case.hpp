// Test scene shared by the end-to-end and post tests: a blunt Arne steel block (hexahedra,
// elastic) strikes a 4 mm Weldox 460 E plate of particles (Johnson–Cook with damage, heating
// and the Mie–Grüneisen EOS) at 800 m/s for 15 µs, both materials from cases/materials. The
// block starts 3 mm above the plate, beyond the 2h = 2.4 mm reach of contact.
#pragma once

#include <string>

namespace sphfem::test {

// Plate: a square of side 2 × plate_half (m), 1 mm lattice. Block: a square prism of side
// 2 × block_half and length block_length (m), 1 mm hexahedra. `quarter`: the quarter x, y ≥ 0
// with symmetry planes x = 0 and y = 0 on both bodies.
inline std::string punch_case(double plate_half, double block_half, double block_length,
                              bool quarter = false) {
  const std::string materials = std::string(SPHFEM_SOURCE_DIR) + "/cases/materials/";
  const auto n = [](double v) { return std::to_string(v); };
  const auto low = [&](double half) { return quarter ? std::string("0") : n(-half); };
  return "name: punch\n"
         "time: {end: 1.5e-5, cfl: 0.5, output_interval: 5.0e-6, history_interval: 1.0e-7}\n"
         "materials:\n"
         "  weldox460e: {library: " +
         materials + "weldox460e.yaml}\n  arne: {library: " + materials +
         "arne.yaml}\n"
         "bodies:\n"
         "  plate:\n"
         "    method: sph\n"
         "    geometry: {box: {min: [" +
         low(plate_half) + ", " + low(plate_half) + ", -0.004], max: [" + n(plate_half) + ", " +
         n(plate_half) +
         ", 0.0]}}\n"
         "    spacing: 0.001\n"
         "    material: weldox460e\n"
         "  projectile:\n"
         "    method: fem\n"
         "    geometry: {box: {min: [" +
         low(block_half) + ", " + low(block_half) + ", 0.003], max: [" + n(block_half) + ", " +
         n(block_half) + ", " + n(0.003 + block_length) +
         "]}}\n"
         "    element_size: 0.001\n"
         "    material: arne\n"
         "    velocity: [0, 0, -800]\n"
         "contact:\n"
         "  - {bodies: [plate, projectile], model: kernel, penalty: 1.0e11, exponent: 2}\n" +
         (quarter ? "boundary_conditions:\n"
                    "  - {type: symmetry, body: plate, face: xmin}\n"
                    "  - {type: symmetry, body: plate, face: ymin}\n"
                    "  - {type: symmetry, body: projectile, face: xmin}\n"
                    "  - {type: symmetry, body: projectile, face: ymin}\n"
                  : "");
}

} // namespace sphfem::test
