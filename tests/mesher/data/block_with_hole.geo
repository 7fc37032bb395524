// Fixture for tests/mesher/lattice_test.cpp: a 40 × 30 × 20 mm block with a spherical hole of
// radius 6 mm at its centre (OpenCASCADE kernel): a volume with an inner boundary surface.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.04, 0.03, 0.02};
Sphere(2) = {0.02, 0.015, 0.01, 0.006};
BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; }
