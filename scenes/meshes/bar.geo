// Source of bar.msh (gmsh -3 bar.geo -format msh41 -o bar.msh): a 0.2 x 0.2 x 1 bar of
// 4 x 4 x 20 hexahedra along z, with the two end faces as named physical surfaces.
Point(1) = {-0.1, -0.1, 0}; Point(2) = {0.1, -0.1, 0}; Point(3) = {0.1, 0.1, 0}; Point(4) = {-0.1, 0.1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 5; Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {0, 0, 1} { Surface{1}; Layers{20}; Recombine; };
Physical Volume("solid") = {out[1]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
