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
  TopoDS_Shape Shape; ///< the shape with each joined solid replaced (the input where none is)
  int Joined = 0;     ///< faces found inside another and joined
  int LeftAlone = 0;  ///< pairs found but not joined (the warnings say where and why)
  int Turned = 0;     ///< shells the transfer made cavities that are bodies, turned back
};

/// Finds, in each solid of `shape`, the plane, cylinder and sphere faces that lie on one surface
/// (within `tolerance`) with opposite outward normals and overlap over an area. Where one of the
/// two (with a single wire) lies inside the other, the bodies are joined: a plane face is removed
/// and its wire added to the other as a hole (its edges then join the touching body's side faces
/// to the other body's face), else the solid is made again from its faces by OpenCASCADE's
/// volume maker. The joined solid must be valid, closed, of the same volume and no more
/// non-manifold, or the solid stays as it was. Faces with the same outline (a cut of no width)
/// are left alone; other overlaps are left with a warning. Each join and each pair left gets a
/// warning in `warnings`, naming where it lies (docs/Robustness.md, item 6). Before that, a
/// shell of a solid other than its outer one whose inside lies outside the outer shell's
/// material (a body within another's bore, which OpenCASCADE's transfer makes the other's
/// cavity) is turned back into a body, with a warning.
TouchingFacesResult JoinBodiesTouchingFaceToFace(
  const TopoDS_Shape& shape, double tolerance, std::vector<std::string>& warnings);
} // namespace brt
