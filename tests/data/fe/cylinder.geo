// Cylinder for the fe unit tests (tests/unit/test_fe_assembly.f90): radius 0.02 m, length
// 0.05 m along z from the origin. Meshed with -order 2, its boundary Tet10/Tri6 are curved
// (edge nodes on the cylinder), which tests isoparametric mass, volume and area. Only the
// lateral face is a physical surface, so only its triangles are saved.
SetFactory("OpenCASCADE");
Cylinder(1) = {0, 0, 0, 0, 0, 0.05, 0.02};
MeshSize{ PointsOf{ Volume{1}; } } = 0.01;
Physical Volume("body", 1) = {1};
Physical Surface("lateral", 2) = {1};
