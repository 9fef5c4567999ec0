// Dog-bone tensile specimen for PeriDeal: an all-hexahedral Gmsh mesh.
//
// The specimen of the Peridigm overview paper's tensile test (section 3.5.1):
// 101.6 mm long (x), 12.7 mm wide at the grips, 6.35 mm wide in the reduced
// section, 3.15 mm thick (z). The origin is the specimen's centre. Lengths are
// in metres. The reduced section is 31.75 mm long and meets the grips through
// fillets of radius 12.7 mm (the ASTM E8 proportions in inches: 1.25 and 0.5).
//
// Cells have edges of about h = 3.15 mm / n (n layers through the thickness):
// the reduced section and the grips are structured (transfinite), the fillets
// are meshed with quadrilaterals of size h; everything is extruded through the
// thickness in n layers. Each cell becomes one peridynamic point.
//
//   n = 4: 6 852 cells   n = 6: 22 980   n = 8: 53 712   n = 10: 105 630
//   n = 12: 182 508 (Gmsh 4.8.4 of Debian 12; the fillets' free mesh may
//   differ with other Gmsh versions)
//
// Volume physical group 1 "specimen" holds every cell.
//
// Generate a mesh (n = 4 unless set; the committed dogbone_4.msh is n = 4):
//   gmsh -3 -format msh22 -setnumber n 6 dogbone.geo -o dogbone_6.msh

DefineConstant[ n = {4, Name "layers through the thickness"} ];

L  = 101.6e-3;  // overall length
Wg = 12.7e-3;   // grip width
Wr = 6.35e-3;   // reduced-section width
T  = 3.15e-3;   // thickness
Lr = 31.75e-3;  // reduced-section length
R  = 12.7e-3;   // fillet radius

h = T / n;
a = Lr / 2;                                   // end of the reduced section
s = Sqrt(R^2 - (R - (Wg - Wr) / 2)^2);        // fillet length along x
b = a + s;                                    // start of the grip

nr = Round(Lr / h);          // cells along the reduced section
nw = Round(Wr / h);          // cells across the reduced section
ng = Round(Wg / h);          // cells across the grip
nl = Round((L / 2 - b) / h); // cells along a grip
nf = Round(1.1 * s / h);     // cells along a fillet arc (it is longer than s)

Mesh.Algorithm = 5;              // Delaunay, then recombined: all quadrilaterals
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1; // blossom
Mesh.CharacteristicLengthMin = h;
Mesh.CharacteristicLengthMax = h;

// Corners of the reduced section and of the grips, and the fillet centres.
Point(1)  = {-a, -Wr / 2, -T / 2};
Point(2)  = { a, -Wr / 2, -T / 2};
Point(3)  = { a,  Wr / 2, -T / 2};
Point(4)  = {-a,  Wr / 2, -T / 2};
Point(5)  = { b, -Wg / 2, -T / 2};
Point(6)  = { b,  Wg / 2, -T / 2};
Point(7)  = {-b, -Wg / 2, -T / 2};
Point(8)  = {-b,  Wg / 2, -T / 2};
Point(9)  = { L / 2, -Wg / 2, -T / 2};
Point(10) = { L / 2,  Wg / 2, -T / 2};
Point(11) = {-L / 2, -Wg / 2, -T / 2};
Point(12) = {-L / 2,  Wg / 2, -T / 2};
Point(13) = { a, -Wr / 2 - R, -T / 2};
Point(14) = { a,  Wr / 2 + R, -T / 2};
Point(15) = {-a, -Wr / 2 - R, -T / 2};
Point(16) = {-a,  Wr / 2 + R, -T / 2};

// Reduced section.
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
// Fillets: arcs from the reduced section out to the grips.
Circle(5) = {2, 13, 5};
Circle(6) = {3, 14, 6};
Circle(7) = {1, 15, 7};
Circle(8) = {4, 16, 8};
Line(9)  = {5, 6};
Line(10) = {7, 8};
// Grips.
Line(11) = {5, 9};
Line(12) = {9, 10};
Line(13) = {10, 6};
Line(14) = {7, 11};
Line(15) = {11, 12};
Line(16) = {12, 8};

Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 9, -6, -2};
Curve Loop(3) = {-7, -4, 8, -10};
Curve Loop(4) = {11, 12, 13, -9};
Curve Loop(5) = {14, 15, 16, -10};
Plane Surface(1) = {1};
Plane Surface(2) = {2};
Plane Surface(3) = {3};
Plane Surface(4) = {4};
Plane Surface(5) = {5};

Transfinite Curve{1, 3}          = nr + 1;
Transfinite Curve{2, 4}          = nw + 1;
Transfinite Curve{9, 10, 12, 15} = ng + 1;
Transfinite Curve{11, 13, 14, 16} = nl + 1;
Transfinite Curve{5, 6, 7, 8}    = nf + 1;
Transfinite Surface{1, 4, 5};
Recombine Surface{1, 2, 3, 4, 5};

v[] = Extrude {0, 0, T} { Surface{1, 2, 3, 4, 5}; Layers{n}; Recombine; };
Physical Volume("specimen", 1) = {v[1], v[7], v[13], v[19], v[25]};
