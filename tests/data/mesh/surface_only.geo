// Toolchain pitfall 13 on purpose: a physical surface but no Physical Volume, so gmsh -3 saves
// the triangles of "left" and no tetrahedra. The reader must say so.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.3, 0.2, 0.1};
eps = 1e-6;
Physical Surface("left") = Surface In BoundingBox {-eps, -eps, -eps, eps, 0.2 + eps, 0.1 + eps};
Mesh.CharacteristicLengthMax = 0.1;
