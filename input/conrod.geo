// Connecting rod of the reference engine (docs/scene.md), one OpenCASCADE volume.
// Units: metres. The rod axis is y; big end centred at the origin, small end at (0, 0.150, 0).
//   big end     ring, bore r 0.018, outer r 0.032, z in [-0.012, 0.012]
//   small end   ring, bore r 0.010, outer r 0.017, z in [-0.012, 0.012], centre (0, 0.150, 0)
//   shank       box x in [-0.009, 0.009], y in [0, 0.150], z in [-0.008, 0.008]
// The two solid discs and the shank are fused first and the bores cut afterwards, so the shank
// does not fill them.
// Parameters (set from the command line with -setnumber, e.g. `gmsh -3 -setnumber lc 0.004`):
//   lc     target element size [m], default 0.005 (Mesh.MeshSizeMax; -clmax does NOT work:
//          the .geo sets the option after the command line)
//   order  element order, default 2 (Tet10 with curved boundary nodes); 1 gives Tet4
//          (`-order 1` does NOT work either, for the same reason: use -setnumber order 1)
// Physical groups (only their elements are saved):
//   Volume  "conrod" (1)
//   Surface "big_end" (1), "small_end" (2): the bore faces; areas 2 pi r t = 2.7143e-3,
//           1.5080e-3 m^2.
// Each group is checked to hold exactly one surface: a failed check stops gmsh with exit code 1.
SetFactory("OpenCASCADE");
If (!Exists(lc))
   lc = 0.005;
EndIf
If (!Exists(order))
   order = 2;
EndIf

Cylinder(1) = {0, 0, -0.012, 0, 0, 0.024, 0.032};                  // big end, solid
Cylinder(2) = {0, 0.150, -0.012, 0, 0, 0.024, 0.017};              // small end, solid
Box(3) = {-0.009, 0, -0.008, 0.018, 0.150, 0.016};                 // shank
Cylinder(4) = {0, 0, -0.012, 0, 0, 0.024, 0.018};                  // big-end bore
Cylinder(5) = {0, 0.150, -0.012, 0, 0, 0.024, 0.010};              // small-end bore
body() = BooleanUnion{ Volume{1}; Delete; }{ Volume{2, 3}; Delete; };
conrod() = BooleanDifference{ Volume{body()}; Delete; }{ Volume{4, 5}; Delete; };
If (#conrod() != 1)
   Error("conrod.geo: the union and cut gave %g volumes, expected 1", #conrod());
   Exit;
EndIf

// Bore faces: the only surfaces inside a box tight around each bore cylinder.
e = 1.0e-4;
big() = Surface In BoundingBox{-0.018 - e, -0.018 - e, -0.012 - e, 0.018 + e, 0.018 + e, 0.012 + e};
small() = Surface In BoundingBox{-0.010 - e, 0.140 - e, -0.012 - e,
                                 0.010 + e, 0.160 + e, 0.012 + e};
If (#big() != 1 || #small() != 1)
   Error("conrod.geo: bore faces big_end, small_end: found %g, %g surfaces, expected 1 each",
         #big(), #small());
   Exit;
EndIf

Physical Volume("conrod", 1) = conrod();
Physical Surface("big_end", 1) = big();
Physical Surface("small_end", 2) = small();

Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeMax = lc;
Mesh.ElementOrder = order;
Mesh.Optimize = 1;
