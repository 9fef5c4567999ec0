// The section of a thin plate, 1 x 0.5, in 10 x 5 first-order quadrilaterals
// in the plane z = 0, for Discretization/Gmsh/Extrusion thickness
// (tests/physics/gmsh_extruded.prm). Surface group 1: the plate (material
// id 1); curve group 10: the edge x = 0 (the side face's boundary id).
// gmsh -2 thin_plate_section.geo -o thin_plate_section.msh
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {1, 0.5, 0};
Point(4) = {0, 0.5, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 11;
Transfinite Curve{2, 4} = 6;
Transfinite Surface{1};
Recombine Surface{1};
Physical Surface(1) = {1};
Physical Curve(10) = {4};
Mesh.MshFileVersion = 2.2;
