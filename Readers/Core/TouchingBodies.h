#pragma once
// Bodies touching face to face inside one shell (docs/Robustness.md, "Bodies touching face to
// face"). Some exporters write two bodies that touch over an area as one solid whose shell holds
// both bodies' faces: a boss's end face lies on the plate's face, the two with opposite outward
// normals, and OpenCASCADE calls the solid valid. The shared area is then an inner wall: the
// samples on it measure one body, and the spheres of both bodies end at it.
#include <TopoDS_Shape.hxx>

#include <string>
#include <vector>

namespace brt
{
struct TouchingFacesResult
{
  TopoDS_Shape Shape; ///< the shape with each joined pair repaired (the input where none is)
  int Joined = 0;     ///< faces removed, each cut out of the face it lay on
  int LeftAlone = 0;  ///< pairs found but not repaired (the warnings say where and why)
};

/// Finds, in each solid of `shape`, the plane faces that lie on each other (within `tolerance`)
/// with opposite outward normals and overlap over an area. Where one of the two (with a single
/// wire) lies strictly inside the other, and no hole of the other lies inside it, it is removed and
/// its wire is added to the other as a hole: its edges then join the touching body's side faces to
/// the other body's face, and the shell bounds the two bodies as one, as they are meant to be. The
/// repaired face's area must be the two faces' difference and the solid must stay closed, or the
/// pair is left as it was. Each repair and each pair left as it is gets a warning in `warnings`,
/// naming where it lies.
TouchingFacesResult JoinBodiesTouchingFaceToFace(
  const TopoDS_Shape& shape, double tolerance, std::vector<std::string>& warnings);
} // namespace brt
