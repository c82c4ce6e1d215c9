// Prismatic test beam for the accuracy test of the pipeline: a solid circular cylinder.
// Units: metres. Axis x, radius 0.010, length 0.200, from x = 0 to x = 0.200.
// Mesh: the x = 0 disc is meshed with triangles of size lc and swept along x in
// ceil(0.200/lc) layers, each prism split into three tetrahedra. (An unstructured Delaunay mesh
// of this slender cylinder gave, at some lc, tetrahedra with all four vertices on the lateral
// face, which the curved Tet10 nodes flatten or invert: Gmsh 4.8.4 reported worst distortion
// 0.002 at lc = 0.004 and -0.0002 at lc = 0.006 with Mesh.Algorithm = 5. The swept mesh has
// worst distortion 1 at every lc tried from 0.002 to 0.008.)
// Parameters (set from the command line with -setnumber, e.g. `gmsh -3 -setnumber lc 0.003`):
//   lc     target element size [m], default 0.004 (Mesh.MeshSizeMax and the layer thickness;
//          -clmax does NOT work: the .geo sets the option after the command line)
//   order  element order, default 2 (Tet10 with curved boundary nodes); 1 gives Tet4
//          (`-order 1` does NOT work either, for the same reason: use -setnumber order 1)
// Physical groups (only their elements are saved):
//   Volume  "beam" (1)
//   Surface "end0" (1): the disc at x = 0;  "end1" (2): the disc at x = 0.200 (area pi r^2 each;
//           the two discs carry the same triangulation, shifted by 0.200 along x)
// Each group is checked to hold exactly one surface: a failed check stops gmsh with exit code 1.
SetFactory("OpenCASCADE");
If (!Exists(lc))
   lc = 0.004;
EndIf
If (!Exists(order))
   order = 2;
EndIf

Disk(1) = {0, 0, 0, 0.010, 0.010};                        // in the plane z = 0, normal +z
Rotate {{0, 1, 0}, {0, 0, 0}, Pi/2} { Surface{1}; }       // now in the plane x = 0, normal +x
layers = Ceil(0.200/lc - 1.0e-9);
out() = Extrude {0.200, 0, 0} { Surface{1}; Layers{layers}; };   // out(1) is the volume

e = 1.0e-4;
end0() = Surface In BoundingBox{-e, -0.010 - e, -0.010 - e, e, 0.010 + e, 0.010 + e};
end1() = Surface In BoundingBox{0.200 - e, -0.010 - e, -0.010 - e, 0.200 + e, 0.010 + e, 0.010 + e};
If (#end0() != 1 || #end1() != 1)
   Error("beam.geo: end faces end0, end1: found %g, %g surfaces, expected 1 each",
         #end0(), #end1());
   Exit;
EndIf

Physical Volume("beam", 1) = {out(1)};
Physical Surface("end0", 1) = end0();
Physical Surface("end1", 2) = end1();

Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeMax = lc;
Mesh.ElementOrder = order;
Mesh.Optimize = 1;
