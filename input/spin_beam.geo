// Rotating-beam spin-up benchmark (Kane, Ryan & Banerjee, J. Guidance 10 (1987) 139), scaled:
// a straight cantilever of square cross-section for tests/unit/test_modes_geometric_stiffness
// and test_mbs_spin_up. Units: metres. Axis x from the root x = 0 to the tip x = L = 10; square
// cross-section a x a = 0.2 x 0.2 centred on the x axis (slenderness L/a = 50, L over the radius
// of gyration 173; Kane's beam has 447: a stockier beam keeps the Tet10 mesh small, and with
// E chosen so that EI/(rho A) equals Kane's, the Euler-Bernoulli dynamics are the same).
// Mesh: structured; the root face is cut into (a/lc)^2 squares of two triangles each and swept
// along x in L/lc layers, each prism split into three tetrahedra (as input/beam.geo).
// Parameters (set from the command line with -setnumber; -clmax and -order do NOT work, the
// .geo sets the options after the command line):
//   lc     element size [m], default 0.2 (one element across); a/lc must be an integer
//   order  element order, default 2 (Tet10); 1 gives Tet4
//   along_z  1: the same beam with its axis along z (root face at z = 0, tip at z = L, the
//          section's sides along x and y) for a spin about the beam's own axis (a mechanism's
//          driving constraint turns a body about z: tests/unit/test_mbs_spin_axis.f90);
//          default 0 (axis x)
// Physical groups (only their elements are saved):
//   Volume  "beam" (1)
//   Surface "root" (1): the square at x = 0;  "tip" (2): the square at x = L
If (!Exists(lc))
   lc = 0.2;
EndIf
If (!Exists(order))
   order = 2;
EndIf
If (!Exists(along_z))
   along_z = 0;
EndIf
L = 10.0;
a = 0.2;
across = Round(a/lc);
If (Fabs(across*lc - a) > 1.0e-9 || across < 1)
   Error("spin_beam.geo: a/lc = %g must be a positive integer", a/lc);
   Exit;
EndIf

If (along_z)
   Point(1) = {-a/2, -a/2, 0};
   Point(2) = {a/2, -a/2, 0};
   Point(3) = {a/2, a/2, 0};
   Point(4) = {-a/2, a/2, 0};
Else
   Point(1) = {0, -a/2, -a/2};
   Point(2) = {0, a/2, -a/2};
   Point(3) = {0, a/2, a/2};
   Point(4) = {0, -a/2, a/2};
EndIf
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};                                   // normal along the beam axis
Transfinite Curve{1, 2, 3, 4} = across + 1;
Transfinite Surface{1} = {1, 2, 3, 4} Alternate;
layers = Round(L/lc);
direction[] = {L, 0, 0};
If (along_z)
   direction[] = {0, 0, L};
EndIf
out[] = Extrude {direction[0], direction[1], direction[2]} { Surface{1}; Layers{layers}; };
// out[0] tip face, out[1] volume

Physical Volume("beam", 1) = {out[1]};
Physical Surface("root", 1) = {1};
Physical Surface("tip", 2) = {out[0]};

Mesh.ElementOrder = order;
Mesh.SecondOrderLinear = 1;
