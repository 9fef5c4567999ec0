// Two-material bar for PeriDeal: an all-hexahedral Gmsh mesh.
//
// A bar 80 mm x 20 mm x 20 mm along x, made of two halves:
//   volume physical group 1 "left_half"   0    <= x <= 0.04
//   volume physical group 2 "right_half"  0.04 <= x <= 0.08
//   surface physical group 10 "left_end"  the end face x = 0
// Transfinite + Recombine give 10 x 5 x 5 hexahedra per half (spacing
// 4 mm): 500 cells, i.e. 500 peridynamic points; the end face x = 0
// has 5 x 5 = 25 cells.
//
// PeriDeal reads the volume groups as material ids (Blocks/<name>/Material
// ids) and the surface group as boundary id 10 (a Region of Type Physical
// group with Physical group dimension 2).
//
// Regenerate the committed mesh with:
//   gmsh -3 -format msh22 two_material_bar.geo -o two_material_bar.msh

L  = 0.04;   // length of each half
W  = 0.02;   // width (y) and height (z)
nx = 10;     // cells along x in each half
ny = 5;      // cells along y
nz = 5;      // cells along z

Point(1) = {0,   0, 0};
Point(2) = {L,   0, 0};
Point(3) = {2*L, 0, 0};
Point(4) = {0,   W, 0};
Point(5) = {L,   W, 0};
Point(6) = {2*L, W, 0};

Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {4, 5};
Line(4) = {5, 6};
Line(5) = {1, 4};
Line(6) = {2, 5};
Line(7) = {3, 6};

Curve Loop(1) = {1, 6, -3, -5};
Curve Loop(2) = {2, 7, -4, -6};
Plane Surface(1) = {1};
Plane Surface(2) = {2};

Transfinite Curve{1, 2, 3, 4} = nx + 1;
Transfinite Curve{5, 6, 7}    = ny + 1;
Transfinite Surface{1, 2};
Recombine Surface{1, 2};

// Extruding the quadrilaterals with Layers + Recombine gives hexahedra.
left[]  = Extrude {0, 0, W} { Surface{1}; Layers{nz}; Recombine; };
right[] = Extrude {0, 0, W} { Surface{2}; Layers{nz}; Recombine; };
// left[1] is the volume; left[5] is the face swept by line 5, i.e. x = 0.

Physical Volume("left_half", 1)  = {left[1]};
Physical Volume("right_half", 2) = {right[1]};
Physical Surface("left_end", 10) = {left[5]};
