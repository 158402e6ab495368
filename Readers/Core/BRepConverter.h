// BRepThickness: conversion of an OpenCASCADE shape into bicubic Bezier patches, cubic trimming
// loops, cubic 3D edges and a display tessellation (docs/DataContract.md). Free of VTK.
#pragma once

#include "BRepModel.h"

#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>

#include <array>

#include <functional>
#include <vector>

class TopoDS_Shape;
class TopoDS_Face;

namespace brt
{

struct ConversionOptions
{
  /// Max distance between a Bezier patch or edge segment and the exact geometry (model units).
  double Tolerance = 1e-4;
  /// Run ShapeFix on the shape before converting.
  bool Heal = true;
  /// Display mesh: max chordal deviation; <= 0 picks 1e-3 of the bounding-box diagonal.
  double LinearDeflection = 0.0;
  /// Display mesh: max angle between adjacent normals (radians).
  double AngularDeflection = 0.35;
  /// Display mesh: triangles are split until no edge is longer; <= 0 picks 1/50 of the
  /// bounding-box diagonal. This sets the density of the thickness samples s0.
  double MaxEdgeLength = 0.0;
  /// Display mesh: after each split of the refinement, make the new triangles' edges Delaunay on
  /// the surface (flips that keep the chordal and angular deflection): well-shaped triangles and
  /// 1.3-16x fewer vertices on real parts, where plain bisection keeps the coarse mesh's slivers
  /// (a long cylinder's side ends at 26,345 vertices whatever its size). Off by default: the
  /// midsurface's outline rule still depends on the sliver mesh of plane faces; SliverRatio and
  /// SliverVertices flip the faces where bisection runs away (docs/Design.md, "Display mesh").
  bool DelaunayRefinement = false;
  /// Without DelaunayRefinement, a face whose bisection mesh would hold more than SliverRatio
  /// times the vertices of its flipped mesh and more than SliverVertices gets the flipped mesh:
  /// a sliver strip that bisection refines far below the edge limit (the side of a cylinder
  /// 1 m long: 26,345 vertices where 1,374 meet the same limits), where the samples' time and
  /// memory run away; SliverRatio <= 0: bisection on every face (docs/Design.md, "Display mesh").
  double SliverRatio = 4.0;
  int SliverVertices = 10000;
  /// Patches longer than this (control-net length, model units) are split exactly, so that
  /// single-precision evaluation stays accurate (the paper's "relatively flat patches");
  /// <= 0 picks 1/8 of the bounding-box diagonal.
  double MaxPatchSize = 0.0;
  /// Cap on the Bezier patches of one face (bounds the refinement of the fit).
  int MaxPatchesPerFace = 16384;
  /// Cap on the vertices of one face's display mesh (bounds the refinement).
  int MaxVerticesPerFace = 200000;
  /// Random (u,v) per face at which the patches are checked against the exact surface.
  int DeviationSamples = 1000;
  /// Called with a fraction in [0,1]; return false to abort (throws std::runtime_error).
  std::function<bool(double)> Progress;
};

/// Converts `shape` (healed first if requested). Throws std::runtime_error if the shape holds no
/// face or the conversion is aborted. Per-face problems do not throw: they land in
/// model.Stats.Warnings and the per-face figures.
/// If `faces` is given it receives the healed faces, model.Faces[i] being (*faces)[i].
BRepModel ConvertShape(const TopoDS_Shape& shape, const ConversionOptions& options,
  std::vector<TopoDS_Face>* faces = nullptr);

/// Meshes again, one by one, the faces of `faceMap` that BRepMesh left without a triangulation,
/// and returns how many got one. BRepMesh fails on some faces whose wires are valid (status
/// Failure): Ploopy's scroll-wheel holder's cone, its top circle written in two arcs, one past
/// 2 pi; the planes and small B-spline faces of SolidWorks's headbands. Each try meshes a copy
/// of the face (its own edges, the same surface and parameters) without the notches of its
/// wires (two edges in a row on one curve, the second turning back), until one gives a
/// triangulation: at `deflection` where the face had a notch; at 4 times it with BRepMesh's
/// Delabella algorithm, then its Watson one; at 1/4 of it for a face within ten deflections
/// across (a failing try on a large face took seconds); last, MeshThroughBSplines. The
/// triangulation goes on the face, with its edges' polygons on the face's edges (both of a
/// seam's; none for a notch's edges). The display mesh's refinement makes such a face's mesh as
/// fine as the others'. A face no try meshes, or on which OpenCASCADE throws, is left as it was.
int MeshFacesLeftWithoutTriangulation(
  const TopTools_IndexedMapOfShape& faceMap, double deflection, double angularDeflection);

/// An edge of a face and its polygons on a triangulation: the second only for a seam (its
/// reversed use).
using EdgePolygons = std::pair<TopoDS_Edge, std::array<Handle(Poly_PolygonOnTriangulation), 2>>;

/// A triangulation of `face` made by BRepMesh on a copy converted to B-splines
/// (BRepBuilderAPI_NurbsConvert), mapped back onto the face's own parameters, with the polygons
/// of the face's edges in `polygons`; null where none could be made so. BRepMesh fails on some
/// analytic faces whatever the deflection and meshes their B-spline copies (Voron's power panel:
/// four cones, each a full turn from pi to 3 pi with its top circle in two arcs). Each node
/// keeps its point and gets its (u, v) on the face's surface (within 1e-6 of the face's size),
/// a periodic parameter taken in the face's range where the node sits in the copy's (the
/// conversion keeps the parameters' order); triangles keep the copy's winding in (u, v); each
/// polygon node gets the parameter of its nearest point on the face's edge (a closed edge's
/// first and last nodes its ends). The last try of MeshFacesLeftWithoutTriangulation.
Handle(Poly_Triangulation) MeshThroughBSplines(const TopoDS_Face& face, double deflection,
  double angularDeflection, std::vector<EdgePolygons>& polygons);

/// Parts smaller than this many conversion tolerances across are refused.
constexpr double MinSizeInTolerances = 100.0;

/// The checks every converted model passes before it is solved: ValidateModel (ModelIO.h), a
/// size well above the tolerance, at least one closed manifold solid (open or non-manifold ones
/// are listed in the warnings; the filter flags their samples), and solids turned inside out are
/// reversed (OrientSolids). Throws InputError naming `path`.
void CheckConvertedModel(const std::string& path, BRepModel& model);

/// Reads a STEP file, converts it and checks the result (CheckConvertedModel); the source file name is kept in the model. Throws
/// InputError (StepFile.h) for bad input.
BRepModel ConvertStepFile(const std::string& path, const ConversionOptions& options,
  std::vector<TopoDS_Face>* faces = nullptr);

} // namespace brt
