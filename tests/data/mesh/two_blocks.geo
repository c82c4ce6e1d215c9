// Two conforming blocks for extract_body: "left_block" 0.3 x 0.2 x 0.1 m (volume 6e-3 m^3) at
// x in [0, 0.3] and "right_block" 0.2 x 0.2 x 0.1 m (volume 4e-3 m^3) at x in [0.3, 0.5], sharing
// the face x = 0.3 (physical surface "interface"); "left" is x = 0, "right" is x = 0.5.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.3, 0.2, 0.1};
Box(2) = {0.3, 0, 0, 0.2, 0.2, 0.1};
v() = BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; };
eps = 1e-6;
Physical Volume("left_block") = Volume In BoundingBox {-eps, -eps, -eps, 0.3 + eps, 0.2 + eps,
  0.1 + eps};
Physical Volume("right_block") = Volume In BoundingBox {0.3 - eps, -eps, -eps, 0.5 + eps,
  0.2 + eps, 0.1 + eps};
Physical Surface("left") = Surface In BoundingBox {-eps, -eps, -eps, eps, 0.2 + eps, 0.1 + eps};
Physical Surface("interface") = Surface In BoundingBox {0.3 - eps, -eps, -eps, 0.3 + eps,
  0.2 + eps, 0.1 + eps};
Physical Surface("right") = Surface In BoundingBox {0.5 - eps, -eps, -eps, 0.5 + eps, 0.2 + eps,
  0.1 + eps};
Mesh.CharacteristicLengthMax = 0.05;
