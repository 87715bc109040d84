// Outer ring of a 6208 deep groove ball bearing (the paper's §5 scene), as a
// structured all-hexahedral mesh for FretSim. SI units: metres.
//
//   gmsh -3 bearing_6208_outer_ring.geo -o bearing_6208_outer_ring.msh
//
// Boundary ids (physical surfaces) and material ids (physical volumes) are
// those of fretsim::fem::BoundaryId / MaterialId (fem/include/fretsim/fem/mesh.h).
// Axis = z, mid-plane z = 0.
//
// Dimensions. Catalogue data of 6208 (ISO 15 dimension series 02): bore
// d = 40 mm, outside diameter D = 80 mm, width B = 18 mm; 9 balls of
// Dw = 12.7 mm (1/2 in) in the common designs. The outer ring's internal
// dimensions are not catalogue data; assumed here, as in the usual textbook
// estimates:
//   pitch diameter     dm = (d + D)/2 = 60 mm
//   groove bottom      Rg = (dm + Dw)/2 = 36.35 mm (zero clearance)
//   groove radius      rg = fo Dw, fo = 0.53 (outer conformity) -> 6.731 mm
//   land (shoulder)    Rs = 34.1 mm, i.e. a shoulder diameter of 68.2 mm and a
//                      groove depth Rg - Rs = 2.25 mm = 0.18 Dw
D  = 0.080;
B  = 0.018;
Dw = 0.0127;
dm = 0.060;
fo = 0.53;
Rg = (dm + Dw) / 2;
rg = fo * Dw;
Rs = 0.0341;
Ro = D / 2;
rc = Rg - rg;                   // centre of the groove arc (on z = 0)
zs = Sqrt(rg^2 - (Rs - rc)^2);  // where the arc meets the lands

// Cells: around the circumference (a multiple of 4), through the wall,
// across the groove and across each land.
n_around = 64;
n_radial = 3;
n_groove = 6;
n_land   = 2;

// Cross-section in the x-z plane (x = radius), three blocks: land | groove | land.
Point(1)  = {Rs, 0, -B/2};
Point(2)  = {Ro, 0, -B/2};
Point(3)  = {Ro, 0, -zs};
Point(4)  = {Rs, 0, -zs};
Point(5)  = {Ro, 0,  zs};
Point(6)  = {Rs, 0,  zs};
Point(7)  = {Ro, 0,  B/2};
Point(8)  = {Rs, 0,  B/2};
Point(9)  = {rc, 0,  0};

Line(1)   = {1, 2};   // side z = -B/2
Line(2)   = {2, 3};   // outer, left land
Line(3)   = {4, 3};   // block interface
Line(4)   = {4, 1};   // bore, left land
Line(5)   = {3, 5};   // outer, groove block
Line(6)   = {6, 5};   // block interface
Circle(7) = {6, 9, 4}; // raceway arc
Line(8)   = {5, 7};   // outer, right land
Line(9)   = {7, 8};   // side z = +B/2
Line(10)  = {8, 6};   // bore, right land

// Each loop lists its curves so that the lateral surfaces of the revolution
// come out in a known order (see the bookkeeping below).
Curve Loop(1) = {1, 2, -3, 4};     // side, outer, interface, land
Curve Loop(2) = {3, 5, -6, 7};     // interface, outer, interface, raceway
Curve Loop(3) = {6, 8, 9, 10};     // interface, outer, side, land
Plane Surface(1) = {1};
Plane Surface(2) = {2};
Plane Surface(3) = {3};

Transfinite Curve{1, 3, 6, 9}  = n_radial + 1;
Transfinite Curve{2, 4, 8, 10} = n_land + 1;
Transfinite Curve{5, 7}        = n_groove + 1;
Transfinite Surface{1, 2, 3};
Recombine Surface{1, 2, 3};

raceway[] = {}; lands[] = {}; outer[] = {}; sides[] = {}; volumes[] = {};
source[] = {1, 2, 3};
For quarter In {1:4}
  out[] = Extrude {{0, 0, 1}, {0, 0, 0}, Pi/2} { Surface{source[]}; Layers{n_around/4}; Recombine; };
  // out = [top, volume, lateral surfaces in curve-loop order] per source surface.
  sides[]   += {out[2], out[16]};
  outer[]   += {out[3], out[9], out[15]};
  lands[]   += {out[5], out[17]};
  raceway[] += {out[11]};
  volumes[] += {out[1], out[7], out[13]};
  source[]   = {out[0], out[6], out[12]};
EndFor
// The last quarter ends on the first cross-section: merge the duplicates so
// the ring is closed.
Coherence;

Physical Surface("raceway", 1)    = {raceway[]};
Physical Surface("ring_lands", 2) = {lands[]};
Physical Surface("ring_outer", 3) = {outer[]};
Physical Surface("side_faces", 6) = {sides[]};
Physical Volume("ring", 1)        = {volumes[]};

Mesh.MshFileVersion = 2.2;
Mesh.RecombineAll = 1;
