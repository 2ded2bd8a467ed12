// Source of roller.msh (gmsh -3 roller.geo -format msh41 -o roller.msh): a hollow roller,
// outer radius 0.12 m, inner radius 0.09 m, 0.3 m long, axis along y through the origin
// (y from -0.15 to 0.15), meshed with hexahedra only: the annulus in the xz-plane is four
// structured quarter rings (8 x 1 quadrangles each: 32 around, 1 through the wall), extruded
// in 4 layers along y. Hollow because only its outer surface touches anything and the scene
// prescribes all its nodes (a kinematic body), so the interior would only cost elements.
R = 0.12; r = 0.09; L = 0.3;
n_quarter = 8; n_wall = 1; n_axial = 4;
Point(1) = {0, -L/2, 0};
For q In {0:3}
  a = q * Pi / 2;
  Point(10 + q) = {R * Cos(a), -L/2, R * Sin(a)};
  Point(20 + q) = {r * Cos(a), -L/2, r * Sin(a)};
EndFor
For q In {0:3}
  Circle(10 + q) = {10 + q, 1, 10 + (q + 1) % 4};
  Circle(20 + q) = {20 + q, 1, 20 + (q + 1) % 4};
  Line(30 + q) = {20 + q, 10 + q};
EndFor
For q In {0:3}
  Curve Loop(40 + q) = {30 + q, 10 + q, -(30 + (q + 1) % 4), -(20 + q)};
  Plane Surface(40 + q) = {40 + q};
  Transfinite Curve{10 + q, 20 + q} = n_quarter + 1;
  Transfinite Curve{30 + q} = n_wall + 1;
  Transfinite Surface{40 + q};
  Recombine Surface{40 + q};
EndFor
out[] = Extrude {0, L, 0} { Surface{40:43}; Layers{n_axial}; Recombine; };
Physical Volume("solid") = {out[1], out[7], out[13], out[19]};
