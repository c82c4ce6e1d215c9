// Test box for the mesh reader: 0.3 x 0.2 x 0.1 m (volume 6e-3 m^3), edge lengths all different
// so that an axis mix-up changes the areas. Physical surfaces: "left" (x = 0, area 0.2*0.1 =
// 0.02 m^2), "right" (x = 0.3) and "x_faces" (both: MSH 2.2 then writes their triangles twice);
// a physical curve and a physical point at the end.
// Order and format come from the gmsh command line.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.3, 0.2, 0.1};
eps = 1e-6;
left() = Surface In BoundingBox {-eps, -eps, -eps, eps, 0.2 + eps, 0.1 + eps};
right() = Surface In BoundingBox {0.3 - eps, -eps, -eps, 0.3 + eps, 0.2 + eps, 0.1 + eps};
Physical Volume("block") = {1};
Physical Surface("left") = {left()};
Physical Surface("right") = {right()};
Physical Surface("x_faces") = {left(), right()};
Mesh.CharacteristicLengthMax = 0.05;
// Physical curve "x_edge" (the edge along x at y = z = 0) and physical point "origin" (the corner
// at 0): their line and point elements give the nodes of curve and point groups.
x_edge() = Curve In BoundingBox {-eps, -eps, -eps, 0.3 + eps, eps, eps};
origin() = Point In BoundingBox {-eps, -eps, -eps, eps, eps, eps};
Physical Curve("x_edge") = {x_edge()};
Physical Point("origin") = {origin()};
