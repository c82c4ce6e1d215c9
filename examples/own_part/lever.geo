// A part of your own: a steel lever arm, 200 x 20 x 10 mm (docs/own_part.md).
// Units: metres. Length along x (0 .. 0.200), width along y (0 .. 0.020), thickness along z
// (0 .. 0.010). Its pivot is the end face x = 0 (held rigidly), its tip the end face x = 0.200
// (where a link would act).
// Parameters (from the command line: gmsh -3 -setnumber lc 0.0025 lever.geo):
//   lc     target element size [m], default 0.005 (Mesh.MeshSizeMax)
//   order  element order, default 2 (Tet10); 1 gives Tet4
// Physical groups (only their elements are saved; the case file names them):
//   Volume  "lever" (1): the body (&body volumes = 'lever')
//   Surface "pivot" (1): the face x = 0      (&interface name = 'pivot')
//   Surface "tip"   (2): the face x = 0.200  (&interface name = 'tip')
// Each surface group is checked to hold exactly one surface: a failed check stops gmsh, exit 1.
SetFactory("OpenCASCADE");
If (!Exists(lc))
   lc = 0.005;
EndIf
If (!Exists(order))
   order = 2;
EndIf

length = 0.200;
width = 0.020;
thickness = 0.010;
Box(1) = {0, 0, 0, length, width, thickness};

e = 1.0e-6;
pivot() = Surface In BoundingBox{-e, -e, -e, e, width + e, thickness + e};
tip() = Surface In BoundingBox{length - e, -e, -e, length + e, width + e, thickness + e};
If (#pivot() != 1 || #tip() != 1)
   Error("lever.geo: faces pivot, tip: found %g, %g surfaces, expected 1 each", #pivot(), #tip());
   Exit;
EndIf

Physical Volume("lever", 1) = {1};
Physical Surface("pivot", 1) = pivot();
Physical Surface("tip", 2) = tip();

Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeMax = lc;
Mesh.ElementOrder = order;
Mesh.Optimize = 1;
