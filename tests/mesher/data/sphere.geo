// Fixture for tests/mesher/lattice_test.cpp: a solid sphere of radius 10 mm centred off the
// origin (OpenCASCADE kernel), filled with SPH particles from a geometry file.
SetFactory("OpenCASCADE");
Sphere(1) = {0.003, -0.002, 0.05, 0.01};
