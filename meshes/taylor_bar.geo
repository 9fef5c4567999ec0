// Taylor impact bar for PeriDeal: an all-hexahedral Gmsh mesh of a solid
// cylinder (an O-grid: a square core and four curved patches), the axis
// along z from z = 0 (the impact face) to z = L. Lengths in metres.
//
// The copper rod of the Taylor bar benchmark (Wilkins and Guinan 1973):
// L0 = 32.4 mm, r0 = 3.2 mm. Cells have edges of about h = r0 / n (n across
// the radius); each cell becomes one peridynamic point.
//
// Generate (n = 4 unless set):
//   gmsh -3 -format msh22 -setnumber n 6 taylor_bar.geo -o taylor_bar_6.msh

DefineConstant[ n = {4, Name "cells across the radius"} ];

R = 3.2e-3;   // radius
L = 32.4e-3;  // length
h = R / n;
s = 0.5 * R;            // half side of the core square
c = R / Sqrt(2);        // the circle's points on the diagonals
ns = Round(2 * s / h);  // cells along a side of the core
nr = Round(0.6 * R / h);  // cells from the core to the surface
nz = Round(L / h);      // layers along the axis

Point(1) = {0, 0, 0};
Point(2) = {-s, -s, 0};
Point(3) = {s, -s, 0};
Point(4) = {s, s, 0};
Point(5) = {-s, s, 0};
Point(6) = {-c, -c, 0};
Point(7) = {c, -c, 0};
Point(8) = {c, c, 0};
Point(9) = {-c, c, 0};
Line(1) = {2, 3};
Line(2) = {3, 4};
Line(3) = {4, 5};
Line(4) = {5, 2};
Circle(5) = {6, 1, 7};
Circle(6) = {7, 1, 8};
Circle(7) = {8, 1, 9};
Circle(8) = {9, 1, 6};
Line(9) = {2, 6};
Line(10) = {3, 7};
Line(11) = {4, 8};
Line(12) = {5, 9};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {1, 10, -5, -9};
Curve Loop(3) = {2, 11, -6, -10};
Curve Loop(4) = {3, 12, -7, -11};
Curve Loop(5) = {4, 9, -8, -12};
Plane Surface(1) = {1};
Plane Surface(2) = {2};
Plane Surface(3) = {3};
Plane Surface(4) = {4};
Plane Surface(5) = {5};
Transfinite Curve{1, 2, 3, 4, 5, 6, 7, 8} = ns + 1;
Transfinite Curve{9, 10, 11, 12} = nr + 1;
Transfinite Surface{1, 2, 3, 4, 5};
Recombine Surface{1, 2, 3, 4, 5};

v[] = Extrude {0, 0, L} { Surface{1, 2, 3, 4, 5}; Layers{nz}; Recombine; };
Physical Volume("bar", 1) = {v[1], v[7], v[13], v[19], v[25]};
