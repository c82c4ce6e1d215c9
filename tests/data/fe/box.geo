// Box for the fe unit tests (tests/unit/test_fe_assembly.f90): 1.0 x 0.8 x 0.6 m with its
// corner at (0.1, -0.2, 0.3). Meshed with -order 1 (Tet4) and -order 2 (Tet10) as ctest
// fixtures; the test reads the MSH 2.2 output. The volume and the six faces are physical groups
// (Gmsh saves only elements of physical groups once one exists).
SetFactory("OpenCASCADE");
Box(1) = {0.1, -0.2, 0.3, 1.0, 0.8, 0.6};
MeshSize{ PointsOf{ Volume{1}; } } = 0.3;
Physical Volume("body", 1) = {1};
Physical Surface("faces", 2) = {1, 2, 3, 4, 5, 6};
