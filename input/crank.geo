// Single-throw crankshaft of the reference engine (docs/scene.md), one fused OpenCASCADE volume.
// Units: metres. Crank axis z, pin at +y (crank angle 0).
//   main journal B1  cylinder r 0.020, z in [-0.060, -0.035]
//   web 1            box x in [-0.030, 0.030], y in [-0.030, 0.075], z in [-0.035, -0.0125]
//   crank pin B2     cylinder r 0.018, axis through (0, 0.045), z in [-0.0125, 0.0125]
//   web 2            mirror of web 1, z in [0.0125, 0.035]
//   main journal B3  cylinder r 0.020, z in [0.035, 0.060]
// Parameters (set from the command line with -setnumber, e.g. `gmsh -3 -setnumber lc 0.004`):
//   lc     target element size [m], default 0.006 (Mesh.MeshSizeMax; -clmax does NOT work:
//          the .geo sets the option after the command line)
//   order  element order, default 2 (Tet10 with curved boundary nodes); 1 gives Tet4
//          (`-order 1` does NOT work either, for the same reason: use -setnumber order 1)
// Physical groups (only their elements are saved):
//   Volume  "crank" (1)
//   Surface "B1" (1), "B2" (2), "B3" (3): the lateral cylindrical faces of the journals and of the
//           pin (not the end caps); areas 2 pi r L = 3.1416e-3, 2.8274e-3, 3.1416e-3 m^2.
// The faces are picked by bounding box after the union (the union renumbers them) and each group
// is checked to hold exactly one surface: a failed check stops gmsh with exit code 1, no mesh.
SetFactory("OpenCASCADE");
If (!Exists(lc))
   lc = 0.006;
EndIf
If (!Exists(order))
   order = 2;
EndIf

Cylinder(1) = {0, 0, -0.060, 0, 0, 0.025, 0.020};                 // B1
Box(2) = {-0.030, -0.030, -0.035, 0.060, 0.105, 0.0225};           // web 1
Cylinder(3) = {0, 0.045, -0.0125, 0, 0, 0.025, 0.018};             // B2
Box(4) = {-0.030, -0.030, 0.0125, 0.060, 0.105, 0.0225};           // web 2
Cylinder(5) = {0, 0, 0.035, 0, 0, 0.025, 0.020};                   // B3
crank() = BooleanUnion{ Volume{1}; Delete; }{ Volume{2:5}; Delete; };
If (#crank() != 1)
   Error("crank.geo: the union gave %g volumes, expected 1", #crank());
   Exit;
EndIf

// Lateral faces: the box around each cylinder holds its lateral face and, for the journals, the
// outer end cap (the inner cap is merged into the web face); the cap is removed by a thin box.
e = 1.0e-4;
b1() = Surface In BoundingBox{-0.020 - e, -0.020 - e, -0.060 - e, 0.020 + e, 0.020 + e, -0.035 + e};
cap() = Surface In BoundingBox{-0.020 - e, -0.020 - e, -0.060 - e,
                               0.020 + e, 0.020 + e, -0.060 + e};
b1() -= cap();
b2() = Surface In BoundingBox{-0.018 - e, 0.027 - e, -0.0125 - e, 0.018 + e, 0.063 + e, 0.0125 + e};
b3() = Surface In BoundingBox{-0.020 - e, -0.020 - e, 0.035 - e, 0.020 + e, 0.020 + e, 0.060 + e};
cap() = Surface In BoundingBox{-0.020 - e, -0.020 - e, 0.060 - e, 0.020 + e, 0.020 + e, 0.060 + e};
b3() -= cap();
If (#b1() != 1 || #b2() != 1 || #b3() != 1)
   Error("crank.geo: interface faces B1, B2, B3: found %g, %g, %g surfaces, expected 1 each",
         #b1(), #b2(), #b3());
   Exit;
EndIf

Physical Volume("crank", 1) = crank();
Physical Surface("B1", 1) = b1();
Physical Surface("B2", 2) = b2();
Physical Surface("B3", 3) = b3();

Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeMax = lc;
Mesh.ElementOrder = order;
Mesh.Optimize = 1;
