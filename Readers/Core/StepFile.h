// BRepThickness: reading a STEP file into an OpenCASCADE shape, with input validation.
#pragma once

#include "InputError.h"
#include "StepScan.h"

#include <string>
#include <vector>

class TopoDS_Shape;

namespace brt
{

/// Cheap checks that need no STEP parsing: the path exists, is a regular non-empty readable file,
/// starts with the ISO-10303-21 header and ends with its END-ISO-10303-21 terminator.
/// Throws InputError on the first problem found.
void CheckStepFile(const std::string& path);

struct StepReadResult
{
  std::string LengthUnit = "mm"; ///< unit of the returned shape (OpenCASCADE converts to mm)
  std::string Schema;            ///< FILE_SCHEMA of the file (AP203/AP214/AP242 names)
  int Roots = 0;                 ///< transferable roots found
  /// Solid entities transferred one by one because the roots gave no solid (an AP242 file
  /// whose product structure leads nowhere OpenCASCADE 7.6 follows); 0 if the roots gave one.
  int SolidsTransferredDirectly = 0;
  /// Declared solids (per placement) that OpenCASCADE's transfer split into one solid per body
  /// and that were put back into one solid each (their bodies touch face to face or not: the
  /// conversion joins the ones that touch, docs/Robustness.md item 6)
  int RegroupedSolids = 0;
  int Faces = 0;                 ///< faces in the returned shape
  StepScanResult Scan;           ///< what the text check found (StepScan.h)
  std::vector<std::string> Warnings; ///< faces lost in the transfer, surface models, ...
  double Seconds = 0.0;
};

/// Reads all roots of a STEP file (AP203, AP214, AP242) into one shape, in millimetres. The
/// text is checked first (ScanStepText). Where the roots give no solid, the file's solid
/// entities (MANIFOLD_SOLID_BREP, BREP_WITH_VOIDS, FACETED_BREP) are transferred one by one.
/// Throws InputError if the file is not a readable STEP file or holds no face.
TopoDS_Shape ReadStepFile(const std::string& path, StepReadResult* info = nullptr);

} // namespace brt
