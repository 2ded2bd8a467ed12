// Source of gmsh_box.msh (Gmsh 4.8.4: gmsh -3 gmsh_box.geo -format msh41 -o gmsh_box.msh) and
// of gmsh_box_msh22.msh, gmsh_box_msh22_bin.msh, gmsh_box_msh41_bin.msh (-format msh22 / msh41,
// -bin for binary):
// a 3 x 2 x 2 block of hexahedra on [0,3]x[0,1]x[0,1], made by extruding a transfinite,
// recombined rectangle, with physical groups of every dimension, one of them unnamed.
Point(1) = {0, 0, 0}; Point(2) = {3, 0, 0}; Point(3) = {3, 1, 0}; Point(4) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 4; Transfinite Curve{2, 4} = 3;
Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {0, 0, 1} { Surface{1}; Layers{2}; Recombine; };
Physical Volume("solid") = {out[1]};
Physical Surface("bottom") = {1};
Physical Surface(7) = {out[0]};
Physical Curve("front_edge") = {1};
Physical Point("origin") = {1};
