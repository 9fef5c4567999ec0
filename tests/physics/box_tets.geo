// restart_verlet.prm's block (8 x 4 x 4) in tetrahedra for Discretization/Gmsh/
// Cells as points: two volumes, x < 4 (physical group 1) and x > 4 (2).
// gmsh -3 box_tets.geo -o box_tets.msh -format msh41
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 4, 4, 4};
Box(2) = {4, 0, 0, 4, 4, 4};
Coherence;
Mesh.MeshSizeMin = 2;
Mesh.MeshSizeMax = 2;
Physical Volume(1) = {1};
Physical Volume(2) = {2};
