// Solids whose wall thickness is known in closed form (Data/README.md), for the generator and
// the tests.
#pragma once

#include <TopoDS_Shape.hxx>

namespace brt::analytic
{
TopoDS_Shape Plate(double lx, double ly, double h);              ///< thickness h
TopoDS_Shape Tube(double R, double r, double length);            ///< thickness R - r
TopoDS_Shape SphericalShell(double R, double r);                 ///< thickness R - r
TopoDS_Shape ToroidalShell(double major, double R, double r);    ///< thickness R - r
/// Coaxial cones (radius R1 at z = 0 to R2 at z = height), walls h apart normal to them.
TopoDS_Shape ConicalShell(double R1, double R2, double height, double h);
/// The same shell as a CAD system may write it: each cone's face past its apex (OpenCASCADE's
/// radius R + v sin(angle) negative over the face), the cones opening downwards from apexes at
/// z = 0 and z = -drop on the axis, semi-angle `angle`, between the planes z = top and
/// z = bottom (both below -drop). Thickness drop sin(angle).
TopoDS_Shape ConicalShellPastApex(double angle, double drop, double top, double bottom);
/// A shell between the lemons of two spindle tori (major radius `major` below both minor radii
/// `inner` < `outer`: the part of each torus across the axis from its angle, OpenCASCADE's
/// major + minor cos(v) < 0), between the planes z = -half and z = half. Thickness outer - inner.
TopoDS_Shape LemonShell(double major, double inner, double outer, double half);
TopoDS_Shape HolePlate(double side, double h, double holeRadius); ///< thickness h
/// A side x side x h block with a through hole of radius holeRadius along z at its middle,
/// countersunk at the top: a 45 degree cone from the hole's radius at z = h - sink to
/// holeRadius + sink at z = h. A sphere tangent to the hole s below the cone's edge touches the
/// cone: 2t = 2 s (1 + sqrt 2) while its foot (s / sqrt 2 above the edge) lies on the cone.
TopoDS_Shape CountersunkPlate(double side, double h, double holeRadius, double sink);
/// A side x side x h block with a slot pocket depth deep in its top, centred: a stadium of
/// straight length slotLength between two half-circles of radius slotRadius, along x (the top
/// face a plane whose trim has the slot's outline as a hole, as a mould's parting plane has the
/// cavity's), and a through hole of radius holeRadius at (side / 4, side / 4).
TopoDS_Shape PocketBlock(double side, double h, double slotLength, double slotRadius,
  double depth, double holeRadius);
/// A block under a ridge: its top the polynomial z = H - a x^2 - c x^3 over x in [-L, L], y in
/// [0, W] (a Bezier curve of degree 3 extruded along y), its bottom z = 0 and planes at x = +-L,
/// y = 0 and y = W; every face a polynomial B-spline (BRepBuilderAPI_NurbsConvert), the top of
/// degree 3 along x. A sphere tangent to the top is bounded by the top itself wherever the ridge
/// bends down faster than the sphere (the 2D problem in the plane y = const: eq. 1 over the curve).
/// With stepHeight > 0 the ridge ends at x = stepAt, where a wall rises by stepHeight to a
/// plateau that runs to x = L: a re-entrant corner where the ridge ends. With nurbs = false the
/// faces stay as the prism made them: the top a surface of linear extrusion of the cubic Bezier
/// curve, the others planes.
TopoDS_Shape CubicRidge(double H, double a, double c, double L, double W, double stepAt = 0.0,
  double stepHeight = 0.0, bool nurbs = true);
/// A plate h thick whose end is a half-ellipse: the profile in the plane y = 0 runs along the
/// bottom z = 0 from x = -L to 0, round the ellipse centred at (0, h/2) with semi-axes b along x
/// and h/2 along z to (0, h), back along the top z = h to x = -L and down; extruded along y by W.
/// Every face a B-spline (BRepBuilderAPI_NurbsConvert): the end a rational one that is no
/// cylinder where b differs from h/2, a free-form round whose own curvature bounds the spheres
/// tangent to it (the 2D problem in the plane y = const: eq. 1 over the profile).
TopoDS_Shape EllipticEndPlate(double L, double h, double b, double W);
/// L profile, legs of length `leg` and thickness `h`, extruded by `width`; inner corner filleted.
TopoDS_Shape LBracket(double leg, double h, double width, double filletRadius);
/// Solids whose medial axis is a curve or a point: a rod (cylinder of radius R and length L
/// along z), a ball, a solid ring (torus). Thickness 2R, 2R, 2 minor.
TopoDS_Shape Rod(double R, double length);
TopoDS_Shape Ball(double R);
TopoDS_Shape Ring(double major, double minor);
/// T profile extruded along z by `depth`: flange x in [-fw/2, fw/2], y in [-ft, 0]; web x in
/// [-wt/2, wt/2], y in [0, wh]. Sharp corners. Its mid-planes: y = -ft/2 and x = 0.
TopoDS_Shape TProfile(double fw, double ft, double wh, double wt, double depth);
/// Cross (+) profile extruded along z by `depth`: two bars of length `len` and thickness `h`
/// crossing at the origin, along x and along y. Sharp corners. Mid-planes x = 0 and y = 0.
TopoDS_Shape CrossProfile(double len, double h, double depth);
/// U-channel along y: outer width w (x), height h (z), legs lt thick, floor ft thick, length l;
/// the slot between the legs is w - 2 lt wide (the exterior gap's closed form).
TopoDS_Shape UChannel(double w, double h, double lt, double ft, double l);
/// Two plates lx x ly x h as two solids of one compound, the second `gap` above the first.
TopoDS_Shape TwoPlates(double lx, double ly, double h, double gap);
/// The compound of two shapes (faces, solids), as they are.
TopoDS_Shape CompoundOf(const TopoDS_Shape& a, const TopoDS_Shape& b);
} // namespace brt::analytic
