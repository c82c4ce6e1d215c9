// Slender steel cantilever for the static-sag benchmark (issue 24 item 4, docs/validation.md
// "Flexible benchmarks"; scene input/cantilever_sag.nml). Units: metres. A straight bar along x
// from the root face at x = 0 to the tip face at x = L = 0.4, square cross-section a x a =
// 0.01 x 0.01 centred on the x axis (slenderness L/a = 40), so Euler-Bernoulli theory holds to
// O((a/L)^2): I = a^4/12, the shear term is 6.4e-4 of the bending one (docs/validation.md).
// Mesh: structured, as input/link.geo: the root face is cut into (a/lc)^2 squares of two
// triangles each and swept along x in L/lc layers, each prism split into three tetrahedra;
// straight-sided Tet10 (Mesh.SecondOrderLinear), so the axis node (L, 0, 0) exists whenever
// a/lc is even.
// Parameters (set from the command line with -setnumber; -clmax and -order do NOT work, the
// .geo sets the options after the command line):
//   lc     element size [m], default 0.005 (two elements across); a/lc must be an integer
//   order  element order, default 2 (Tet10); 1 gives Tet4
//   groups 1: also the physical point "tip_corner" and curve "tip_edge" below (mesh
//          cantilever_groups; default 0, so that cantilever.msh keeps its elements)
// Physical groups (only their elements are saved):
//   Volume  "bar" (1)
//   Surface "root" (1): the square at x = 0;  "tip" (2): the square at x = L
//   with groups = 1: Point "tip_corner" (3): the tip's corner (L, -a/2, -a/2);  Curve
//   "tip_edge" (4): the tip's lower edge y = -a/2 (markers at the centre of a physical group,
//   docs/mechanisms.md "Markers at mesh points")
If (!Exists(lc))
   lc = 0.005;
EndIf
If (!Exists(order))
   order = 2;
EndIf
If (!Exists(groups))
   groups = 0;
EndIf
L = 0.4;
a = 0.01;
across = Round(a/lc);
If (Fabs(across*lc - a) > 1.0e-9 || across < 1)
   Error("cantilever.geo: a/lc = %g must be a positive integer", a/lc);
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
Plane Surface(1) = {1};                                   // normal along the bar axis
Transfinite Curve{1, 2, 3, 4} = across + 1;
Transfinite Surface{1} = {1, 2, 3, 4} Alternate;
layers = Round(L/lc);
out[] = Extrude {L, 0, 0} { Surface{1}; Layers{layers}; };
// out[0] tip face, out[1] volume

Physical Volume("bar", 1) = {out[1]};
Physical Surface("root", 1) = {1};
Physical Surface("tip", 2) = {out[0]};
If (groups)
   eps = 1.0e-6;
   corner[] = Point In BoundingBox {L - eps, -a/2 - eps, -a/2 - eps, L + eps, -a/2 + eps, -a/2 + eps};
   edge[] = Curve In BoundingBox {L - eps, -a/2 - eps, -a/2 - eps, L + eps, -a/2 + eps, a/2 + eps};
   Physical Point("tip_corner", 3) = {corner[]};
   Physical Curve("tip_edge", 4) = {edge[]};
EndIf

Mesh.ElementOrder = order;
Mesh.SecondOrderLinear = 1;
