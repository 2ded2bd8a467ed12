// Source of gmsh_two_groups_msh22.msh and gmsh_two_groups_msh22_bin.msh (Gmsh 4.8.4:
// gmsh -3 gmsh_two_groups.geo -format msh22 [-bin] -o ...).
// One hexahedron in two physical volumes and its bottom face in a physical surface: MSH 2
// writes the hexahedron once per volume group, under a new element tag each time.
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 2; Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {0, 0, 1} { Surface{1}; Layers{1}; Recombine; };
Physical Volume("whole") = {out[1]};
Physical Volume("also_whole") = {out[1]};
Physical Surface("bottom") = {1};
