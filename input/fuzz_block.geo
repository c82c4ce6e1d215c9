// Small block for the negative suite (tests/negative): the base meshes that the fuzzer mutates.
// Units: metres. Box 0.040 x 0.020 x 0.020 from the origin, a few hundred tetrahedra.
// Parameters (gmsh -3 -setnumber lc 0.008 -setnumber order 1|2):
//   lc     target element size [m], default 0.008
//   order  element order, default 1 (Tet4); 2 gives Tet10
// Physical groups (only their elements are saved):
//   Volume  "block" (1)
//   Surface "face_a" (1): x = 0;  "face_b" (2): x = 0.040;  "face_c" (3): y = 0.020
// Each group is checked to hold exactly one surface: a failed check stops gmsh with exit code 1.
SetFactory("OpenCASCADE");
If (!Exists(lc))
   lc = 0.008;
EndIf
If (!Exists(order))
   order = 1;
EndIf

Box(1) = {0, 0, 0, 0.040, 0.020, 0.020};

e = 1.0e-4;
face_a() = Surface In BoundingBox{-e, -e, -e, e, 0.020 + e, 0.020 + e};
face_b() = Surface In BoundingBox{0.040 - e, -e, -e, 0.040 + e, 0.020 + e, 0.020 + e};
face_c() = Surface In BoundingBox{-e, 0.020 - e, -e, 0.040 + e, 0.020 + e, 0.020 + e};
If (#face_a() != 1 || #face_b() != 1 || #face_c() != 1)
   Error("fuzz_block.geo: faces face_a, face_b, face_c: found %g, %g, %g surfaces, expected 1 each",
         #face_a(), #face_b(), #face_c());
   Exit;
EndIf

Physical Volume("block", 1) = {1};
Physical Surface("face_a", 1) = face_a();
Physical Surface("face_b", 2) = face_b();
Physical Surface("face_c", 3) = face_c();

Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeMax = lc;
Mesh.ElementOrder = order;
Mesh.Optimize = 1;
