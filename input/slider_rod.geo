// Connecting rod of the flexible slider-crank benchmark (issue 24 item 4; docs/validation.md
// "Flexible benchmarks"; the case input/flexible_slider_crank.nml). Units: metres. A straight
// steel rod along x from end_a at x = 0 (the crank pin) to end_b at x = L = 0.304 (the slider),
// circular cross-section of diameter d = 6 mm centred on the x axis. Straight-sided Tet10 at
// lc = 3 mm make the section a polygon (area 2.546e-5 m^2, 10 % below pi d^2/4; first pinned
// bending mode 122 Hz against 128.4 Hz for the circle).
// The mid-span point (L/2, 0, 0) on the rod's axis is embedded in the volume, so the mesh has a
// node there: the deflection sensor of the case (its Gmsh node tag, the first node of the mesh:
// point entities are numbered first, and this point is Point(1)).
// Parameters (set from the command line with -setnumber; -clmax and -order do NOT work, the
// .geo sets the options after the command line):
//   lc     element size [m], default 0.003 (two elements across the diameter)
//   order  element order, default 2 (Tet10); 1 gives Tet4
// Physical groups (only their elements are saved):
//   Volume  "rod" (1)
//   Surface "end_a" (1): the disc at x = 0;  "end_b" (2): the disc at x = L
If (!Exists(lc))
   lc = 0.003;
EndIf
If (!Exists(order))
   order = 2;
EndIf
L = 0.304;
r = 0.003;

Point(1) = {L/2, 0, 0, lc};                               // mid-span, embedded below
Point(2) = {0, 0, 0, lc};                                 // centre of end_a
Point(3) = {0, r, 0, lc};
Point(4) = {0, 0, r, lc};
Point(5) = {0, -r, 0, lc};
Point(6) = {0, 0, -r, lc};
Circle(1) = {3, 2, 4};
Circle(2) = {4, 2, 5};
Circle(3) = {5, 2, 6};
Circle(4) = {6, 2, 3};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};                                   // normal along the rod axis
out[] = Extrude {L, 0, 0} { Surface{1}; };
// out[0] end_b face, out[1] volume
Point{1} In Volume{out[1]};

Physical Volume("rod", 1) = {out[1]};
Physical Surface("end_a", 1) = {1};
Physical Surface("end_b", 2) = {out[0]};

Mesh.CharacteristicLengthMax = lc;
Mesh.ElementOrder = order;
Mesh.SecondOrderLinear = 1;
