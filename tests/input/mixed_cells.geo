// Two unit squares side by side, one of quadrilaterals, one of triangles,
// extruded by one layer: a mixed mesh of hexahedra and prisms.
// gmsh -3 mixed_cells.geo -o mixed_cells.msh -format msh22
lc = 0.5;
Point(1) = {0, 0, 0, lc}; Point(2) = {1, 0, 0, lc}; Point(3) = {2, 0, 0, lc};
Point(4) = {0, 1, 0, lc}; Point(5) = {1, 1, 0, lc}; Point(6) = {2, 1, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 5}; Line(3) = {5, 4}; Line(4) = {4, 1};
Line(5) = {2, 3}; Line(6) = {3, 6}; Line(7) = {6, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Transfinite Surface{1}; Recombine Surface{1};
Extrude {0, 0, 0.5} { Surface{1, 2}; Layers{1}; Recombine; }
Physical Volume(1) = {1, 2};
