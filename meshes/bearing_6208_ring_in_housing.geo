// Outer ring of a 6208 deep groove ball bearing bonded in a steel housing
// ring (the paper's §5 scene with its housing), as one conforming
// all-hexahedral mesh for FretSim. SI units: metres.
//
//   gmsh -3 bearing_6208_ring_in_housing.geo -o bearing_6208_ring_in_housing.msh
//
// Boundary ids (physical surfaces) and material ids (physical volumes) are
// those of fretsim::fem::BoundaryId / MaterialId (fem/include/fretsim/fem/mesh.h).
// Axis = z, mid-plane z = 0. The ring's outer surface and the housing bore
// coincide (radius D/2); they share their nodes, so the two bodies are bonded
// and that interface carries no physical surface (it is not a boundary).
//
// Ring dimensions as in bearing_6208_outer_ring.geo (catalogue 6208: d = 40 mm,
// D = 80 mm, B = 18 mm, Dw = 12.7 mm; assumed internal dimensions: dm = 60 mm,
// groove bottom Rg = (dm + Dw)/2, groove radius 0.53 Dw, land radius 34.1 mm).
// Housing: bore D/2, outer radius 60 mm (the default of the ring_housing scene,
// `Housing/Outer radius`), same width B.
D  = 0.080;
B  = 0.018;
Dw = 0.0127;
dm = 0.060;
fo = 0.53;
Rg = (dm + Dw) / 2;
rg = fo * Dw;
Rs = 0.0341;
Ro = D / 2;
Rh = 0.060;
rc = Rg - rg;                   // centre of the groove arc (on z = 0)
zs = Sqrt(rg^2 - (Rs - rc)^2);  // where the arc meets the lands

// Cells: around the circumference (a multiple of 4), through the ring wall,
// through the housing wall, across the groove and across each land. The
// housing takes the ring's axial divisions, so the interface is conforming.
n_around  = 64;
n_radial  = 3;
n_housing = 4;
n_groove  = 6;
n_land    = 2;

// Cross-section in the x-z plane (x = radius): ring blocks land | groove | land
// (surfaces 1-3), housing blocks beside them (surfaces 4-6).
Point(1)  = {Rs, 0, -B/2};
Point(2)  = {Ro, 0, -B/2};
Point(3)  = {Ro, 0, -zs};
Point(4)  = {Rs, 0, -zs};
Point(5)  = {Ro, 0,  zs};
Point(6)  = {Rs, 0,  zs};
Point(7)  = {Ro, 0,  B/2};
Point(8)  = {Rs, 0,  B/2};
Point(9)  = {rc, 0,  0};
Point(10) = {Rh, 0, -B/2};
Point(11) = {Rh, 0, -zs};
Point(12) = {Rh, 0,  zs};
Point(13) = {Rh, 0,  B/2};

Line(1)   = {1, 2};   // ring side z = -B/2
Line(2)   = {2, 3};   // ring/housing interface, left land
Line(3)   = {4, 3};   // ring block interface
Line(4)   = {4, 1};   // bore, left land
Line(5)   = {3, 5};   // ring/housing interface, groove block
Line(6)   = {6, 5};   // ring block interface
Circle(7) = {6, 9, 4}; // raceway arc
Line(8)   = {5, 7};   // ring/housing interface, right land
Line(9)   = {7, 8};   // ring side z = +B/2
Line(10)  = {8, 6};   // bore, right land
Line(11)  = {2, 10};  // housing side z = -B/2
Line(12)  = {10, 11}; // housing outer, left
Line(13)  = {3, 11};  // housing block interface
Line(14)  = {11, 12}; // housing outer, middle
Line(15)  = {5, 12};  // housing block interface
Line(16)  = {12, 13}; // housing outer, right
Line(17)  = {7, 13};  // housing side z = +B/2

// Each loop lists its curves so that the lateral surfaces of the revolution
// come out in a known order (see the bookkeeping below); all loops run
// counter-clockwise in the (x, z) plane.
Curve Loop(1) = {1, 2, -3, 4};      // side, interface, block interface, land
Curve Loop(2) = {3, 5, -6, 7};      // block interface, interface, block interface, raceway
Curve Loop(3) = {6, 8, 9, 10};      // block interface, interface, side, land
Curve Loop(4) = {11, 12, -13, -2};  // side, outer, block interface, interface
Curve Loop(5) = {13, 14, -15, -5};  // block interface, outer, block interface, interface
Curve Loop(6) = {15, 16, -17, -8};  // block interface, outer, side, interface
Plane Surface(1) = {1};
Plane Surface(2) = {2};
Plane Surface(3) = {3};
Plane Surface(4) = {4};
Plane Surface(5) = {5};
Plane Surface(6) = {6};

Transfinite Curve{1, 3, 6, 9}      = n_radial + 1;
Transfinite Curve{11, 13, 15, 17}  = n_housing + 1;
Transfinite Curve{2, 4, 8, 10, 12, 16} = n_land + 1;
Transfinite Curve{5, 7, 14}        = n_groove + 1;
Transfinite Surface{1:6};
Recombine Surface{1:6};

raceway[] = {}; lands[] = {}; outer[] = {}; sides[] = {}; ring[] = {}; housing[] = {};
source[] = {1:6};
For quarter In {1:4}
  out[] = Extrude {{0, 0, 1}, {0, 0, 0}, Pi/2} { Surface{source[]}; Layers{n_around/4}; Recombine; };
  // out = [top, volume, lateral surfaces in curve-loop order] per source
  // surface, six entries each: ring blocks at 0, 6, 12, housing at 18, 24, 30.
  sides[]   += {out[2], out[16], out[20], out[34]};
  lands[]   += {out[5], out[17]};
  raceway[] += {out[11]};
  outer[]   += {out[21], out[27], out[33]};
  ring[]    += {out[1], out[7], out[13]};
  housing[] += {out[19], out[25], out[31]};
  source[]   = {out[0], out[6], out[12], out[18], out[24], out[30]};
EndFor
// The last quarter ends on the first cross-section, and neighbouring blocks
// were extruded side by side: merge the duplicates so that the mesh is closed
// and conforming.
Coherence;

Physical Surface("raceway", 1)       = {raceway[]};
Physical Surface("ring_lands", 2)    = {lands[]};
Physical Surface("housing_outer", 5) = {outer[]};
Physical Surface("side_faces", 6)    = {sides[]};
Physical Volume("ring", 1)           = {ring[]};
Physical Volume("housing", 2)        = {housing[]};

Mesh.MshFileVersion = 2.2;
Mesh.RecombineAll = 1;
