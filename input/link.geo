// Slender link of a chain of flexible bodies (issue 24: benchmark_threads and the sparse
// iteration-matrix tests). Units: metres. A straight bar along x from end_a at x = 0 to end_b
// at x = L = 0.3, square cross-section a x a = 0.02 x 0.02 centred on the x axis (slenderness
// L/a = 15). Chains place copies end to end along x (&body position) and join end_b of one
// link to end_a of the next by a revolute joint about z.
// Mesh: structured, as input/spin_beam.geo: the end_a face is cut into (a/lc)^2 squares of two
// triangles each and swept along x in L/lc layers, each prism split into three tetrahedra.
// Parameters (set from the command line with -setnumber; -clmax and -order do NOT work, the
// .geo sets the options after the command line):
//   lc     element size [m], default 0.01 (two elements across); a/lc must be an integer
//   order  element order, default 2 (Tet10); 1 gives Tet4
// Physical groups (only their elements are saved):
//   Volume  "link" (1)
//   Surface "end_a" (1): the square at x = 0;  "end_b" (2): the square at x = L
If (!Exists(lc))
   lc = 0.01;
EndIf
If (!Exists(order))
   order = 2;
EndIf
L = 0.3;
a = 0.02;
across = Round(a/lc);
If (Fabs(across*lc - a) > 1.0e-9 || across < 1)
   Error("link.geo: a/lc = %g must be a positive integer", a/lc);
   Exit;
EndIf

Point(1) = {0, -a/2, -a/2};
Point(2) = {0, a/2, -a/2};
Point(3) = {0, a/2, a/2};
Point(4) = {0, -a/2, a/2};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};                                   // normal along the link axis
Transfinite Curve{1, 2, 3, 4} = across + 1;
Transfinite Surface{1} = {1, 2, 3, 4} Alternate;
layers = Round(L/lc);
out[] = Extrude {L, 0, 0} { Surface{1}; Layers{layers}; };
// out[0] end_b face, out[1] volume

Physical Volume("link", 1) = {out[1]};
Physical Surface("end_a", 1) = {1};
Physical Surface("end_b", 2) = {out[0]};

Mesh.ElementOrder = order;
Mesh.SecondOrderLinear = 1;
