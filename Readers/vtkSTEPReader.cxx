#include "vtkSTEPReader.h"

#include "BRepConverter.h"
#include "StepFile.h"
#include "StepIsolation.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <string>

vtkStandardNewMacro(vtkSTEPReader);

namespace
{
/// Field array with `comps` components and one tuple per item, filled by `fill(item, tuple)`.
template <class ArrayT, class ItemT, class FillT>
void AddArray(vtkFieldData* fd, const char* name, int comps, const std::vector<ItemT>& items,
  FillT fill)
{
  vtkNew<ArrayT> a;
  a->SetName(name);
  a->SetNumberOfComponents(comps);
  a->SetNumberOfTuples(static_cast<vtkIdType>(items.size()));
  for (size_t i = 0; i < items.size(); ++i)
  {
    fill(items[i], a->GetPointer(static_cast<vtkIdType>(i) * comps));
  }
  fd->AddArray(a);
}

void AddScalar(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

void AddString(vtkFieldData* fd, const char* name, std::initializer_list<std::string> values)
{
  vtkNew<vtkStringArray> a;
  a->SetName(name);
  for (const auto& v : values)
    a->InsertNextValue(v);
  fd->AddArray(a);
}

/// Faces [first, last) of piece `piece` out of `pieces`: contiguous ranges of faces with about
/// the same number of mesh vertices each (the mesh is stored face after face).
std::pair<int, int> PieceFaces(const brt::BRepModel& m, int piece, int pieces)
{
  const int nf = static_cast<int>(m.Faces.size());
  if (pieces <= 1)
    return { 0, nf };
  std::vector<size_t> before(nf + 1, 0); // vertices of the faces before face f
  for (int f : m.Mesh.FaceIds)
    ++before[f + 1];
  for (int f = 0; f < nf; ++f)
    before[f + 1] += before[f];
  auto boundary = [&](int k) {
    const double target = static_cast<double>(before[nf]) * k / pieces;
    return static_cast<int>(
      std::lower_bound(before.begin(), before.end(), target) - before.begin());
  };
  return { std::min(boundary(piece), nf), std::min(boundary(piece + 1), nf) };
}

void FillPolyData(const brt::BRepModel& m, vtkPolyData* out, int piece, int pieces)
{
  const brt::DisplayMesh& Mfull = m.Mesh;
  // This piece's part of the mesh: the vertices and triangles of its faces, in their order.
  const auto faces = PieceFaces(m, piece, pieces);
  brt::DisplayMesh M;
  std::vector<int> newId(Mfull.NumberOfPoints(), -1);
  for (size_t i = 0; i < Mfull.NumberOfPoints(); ++i)
  {
    const int f = Mfull.FaceIds[i];
    if (f < faces.first || f >= faces.second)
      continue;
    newId[i] = static_cast<int>(M.FaceIds.size());
    M.FaceIds.push_back(f);
    M.Points.insert(M.Points.end(), &Mfull.Points[3 * i], &Mfull.Points[3 * i] + 3);
    M.Normals.insert(M.Normals.end(), &Mfull.Normals[3 * i], &Mfull.Normals[3 * i] + 3);
    M.UV.insert(M.UV.end(), &Mfull.UV[2 * i], &Mfull.UV[2 * i] + 2);
    if (Mfull.Curvatures.size() == 2 * Mfull.NumberOfPoints())
      M.Curvatures.insert(
        M.Curvatures.end(), &Mfull.Curvatures[2 * i], &Mfull.Curvatures[2 * i] + 2);
  }
  for (size_t t = 0; t < Mfull.TriangleFace.size(); ++t)
  {
    const int f = Mfull.TriangleFace[t];
    if (f < faces.first || f >= faces.second)
      continue;
    M.TriangleFace.push_back(f);
    for (int k = 0; k < 3; ++k)
      M.Triangles.push_back(newId[Mfull.Triangles[3 * t + k]]);
  }

  const vtkIdType n = static_cast<vtkIdType>(M.NumberOfPoints());
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(n);
  if (n > 0)
    std::memcpy(vtkDoubleArray::SafeDownCast(pts->GetData())->GetPointer(0), M.Points.data(),
      sizeof(double) * 3 * n);
  out->SetPoints(pts);

  vtkNew<vtkCellArray> polys;
  const vtkIdType nt = static_cast<vtkIdType>(M.TriangleFace.size());
  polys->AllocateExact(nt, 3 * nt);
  for (vtkIdType t = 0; t < nt; ++t)
  {
    const vtkIdType ids[3] = { M.Triangles[3 * t], M.Triangles[3 * t + 1],
      M.Triangles[3 * t + 2] };
    polys->InsertNextCell(3, ids);
  }
  out->SetPolys(polys);

  auto pointArray = [&](auto array, const char* name, int comps, const auto& values) {
    array->SetName(name);
    array->SetNumberOfComponents(comps);
    array->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n * comps; ++i)
      array->SetValue(i, values[i]);
    return array;
  };
  vtkNew<vtkIntArray> faceIds, solidIds;
  vtkNew<vtkDoubleArray> uv, normals, curvatures;
  std::vector<int> solid(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
    solid[i] = m.Faces[M.FaceIds[i]].Solid;
  out->GetPointData()->AddArray(pointArray(faceIds.Get(), "FaceId", 1, M.FaceIds));
  out->GetPointData()->AddArray(pointArray(solidIds.Get(), "SolidId", 1, solid));
  out->GetPointData()->AddArray(pointArray(uv.Get(), "FaceUV", 2, M.UV));
  out->GetPointData()->SetNormals(pointArray(normals.Get(), "Normals", 3, M.Normals));
  if (M.Curvatures.size() == 2 * M.NumberOfPoints())
    out->GetPointData()->AddArray(
      pointArray(curvatures.Get(), "PrincipalCurvatures", 2, M.Curvatures));
  out->GetPointData()->SetActiveScalars("FaceId");

  vtkNew<vtkIntArray> cellFace;
  cellFace->SetName("FaceId");
  cellFace->SetNumberOfTuples(nt);
  for (vtkIdType t = 0; t < nt; ++t)
    cellFace->SetValue(t, M.TriangleFace[t]);
  out->GetCellData()->AddArray(cellFace);

  // Field data: the converted B-Rep (docs/DataContract.md).
  vtkFieldData* fd = out->GetFieldData();
  AddArray<vtkDoubleArray>(fd, "BezierPatches", 48, m.Patches,
    [](const brt::BezierPatch& p, double* o) { std::copy(p.ControlPoints.begin(), p.ControlPoints.end(), o); });
  AddArray<vtkIntArray>(fd, "PatchFace", 1, m.Patches,
    [](const brt::BezierPatch& p, int* o) { o[0] = p.Face; });
  AddArray<vtkDoubleArray>(fd, "PatchDomain", 4, m.Patches,
    [](const brt::BezierPatch& p, double* o) { std::copy(p.Domain.begin(), p.Domain.end(), o); });

  AddArray<vtkIntArray>(fd, "FaceInfo", 9, m.Faces, [](const brt::Face& f, int* o) {
    const int v[9] = { f.Solid, f.Reversed ? 1 : 0, static_cast<int>(f.Kind), f.FirstPatch,
      f.PatchesU, f.PatchesV, f.FirstLoop, f.LoopCount, f.Rational ? 1 : 0 };
    std::copy(v, v + 9, o);
  });
  AddArray<vtkIntArray>(fd, "FaceDegrees", 2, m.Faces, [](const brt::Face& f, int* o) {
    o[0] = f.DegreeU;
    o[1] = f.DegreeV;
  });
  AddArray<vtkDoubleArray>(fd, "FaceDomain", 4, m.Faces,
    [](const brt::Face& f, double* o) { std::copy(f.Domain.begin(), f.Domain.end(), o); });
  AddArray<vtkDoubleArray>(fd, "FacePeriod", 2, m.Faces,
    [](const brt::Face& f, double* o) { o[0] = f.Period[0]; o[1] = f.Period[1]; });
  AddArray<vtkDoubleArray>(fd, "FaceMaxDeviation", 1, m.Faces,
    [](const brt::Face& f, double* o) { o[0] = f.MaxDeviation; });
  AddArray<vtkDoubleArray>(fd, "FaceUVTolerance", 1, m.Faces,
    [](const brt::Face& f, double* o) { o[0] = f.UVTolerance; });
  if (m.FaceExact.size() == m.Faces.size())
    AddArray<vtkDoubleArray>(fd, "FaceExactSurface", 8, m.FaceExact,
      [](const std::array<double, 8>& e, double* o) { std::copy(e.begin(), e.end(), o); });
  AddArray<vtkDoubleArray>(fd, "LooseVertices", 4, m.LooseVertices,
    [](const std::array<double, 4>& v, double* o) { std::copy(v.begin(), v.end(), o); });
  AddArray<vtkIntArray>(fd, "LooseFaces", 1, m.LooseFaces, [](int f, int* o) { o[0] = f; });
  AddArray<vtkIntArray>(
    fd, "OverlappingFaces", 1, m.OverlappingFaces, [](int f, int* o) { o[0] = f; });

  AddArray<vtkDoubleArray>(fd, "TrimSegments", 8, m.TrimSegments,
    [](const brt::TrimSegment& s, double* o) { std::copy(s.ControlPoints.begin(), s.ControlPoints.end(), o); });
  AddArray<vtkIntArray>(fd, "TrimSegmentInfo", 4, m.TrimSegments, [](const brt::TrimSegment& s, int* o) {
    o[0] = s.Face;
    o[1] = s.Loop;
    o[2] = s.Edge;
    o[3] = s.Reversed ? 1 : 0;
  });
  AddArray<vtkDoubleArray>(fd, "TrimSegmentRange", 2, m.TrimSegments,
    [](const brt::TrimSegment& s, double* o) { o[0] = s.T0; o[1] = s.T1; });
  AddArray<vtkIntArray>(fd, "TrimLoops", 4, m.Loops, [](const brt::TrimLoop& l, int* o) {
    o[0] = l.Face;
    o[1] = l.FirstSegment;
    o[2] = l.SegmentCount;
    o[3] = l.Outer ? 1 : 0;
  });

  AddArray<vtkDoubleArray>(fd, "EdgeSegments", 12, m.EdgeSegments,
    [](const brt::EdgeSegment& s, double* o) { std::copy(s.ControlPoints.begin(), s.ControlPoints.end(), o); });
  AddArray<vtkIntArray>(fd, "EdgeSegmentEdge", 1, m.EdgeSegments,
    [](const brt::EdgeSegment& s, int* o) { o[0] = s.Edge; });
  AddArray<vtkDoubleArray>(fd, "EdgeSegmentRange", 2, m.EdgeSegments,
    [](const brt::EdgeSegment& s, double* o) { o[0] = s.T0; o[1] = s.T1; });
  AddArray<vtkIntArray>(fd, "EdgeFaces", 2, m.Edges,
    [](const brt::Edge& e, int* o) { o[0] = e.Faces[0]; o[1] = e.Faces[1]; });
  AddArray<vtkDoubleArray>(fd, "EdgeRange", 2, m.Edges,
    [](const brt::Edge& e, double* o) { o[0] = e.T0; o[1] = e.T1; });
  AddArray<vtkIntArray>(fd, "EdgeInfo", 4, m.Edges, [](const brt::Edge& e, int* o) {
    o[0] = e.FirstSegment;
    o[1] = e.SegmentCount;
    o[2] = e.Seam ? 1 : 0;
    o[3] = e.FaceCount;
  });

  // Statistics.
  const brt::ConversionStatistics& s = m.Stats;
  AddScalar(fd, "Tolerance", m.Tolerance);
  AddScalar(fd, "NumberOfSolids", s.Solids);
  AddScalar(fd, "NumberOfFaces", s.Faces);
  AddScalar(fd, "NumberOfPatches", s.Patches);
  AddScalar(fd, "NumberOfLoops", s.Loops);
  AddScalar(fd, "NumberOfTrimSegments", s.TrimSegments);
  AddScalar(fd, "NumberOfEdges", s.Edges);
  AddScalar(fd, "NumberOfEdgeSegments", s.EdgeSegments);
  AddScalar(fd, "MaxPatchDeviation", s.MaxPatchDeviation);
  AddScalar(fd, "MaxEdgeDeviation", s.MaxEdgeDeviation);
  AddScalar(fd, "MaxLoopGapUV", s.MaxLoopGap);
  AddScalar(fd, "MaxLoopGap3D", s.MaxLoopGap3D);
  AddScalar(fd, "OpenLoops", s.OpenLoops);
  AddScalar(fd, "FlippedMeshFaces", s.FlippedFaces);
  AddScalar(fd, "RemeshedFaces", s.RemeshedFaces);
  AddScalar(fd, "ReadSeconds", s.ReadSeconds);
  AddScalar(fd, "HealSeconds", s.HealSeconds);
  AddScalar(fd, "ConvertSeconds", s.ConvertSeconds);
  AddScalar(fd, "MeshSeconds", s.MeshSeconds);
  AddString(fd, "SourceFile", { m.SourceFile });
  AddString(fd, "LengthUnit", { m.LengthUnit });
  AddString(fd, "StepSchema", { m.Schema });
  vtkNew<vtkStringArray> warnings;
  warnings->SetName("ConversionWarnings");
  for (const auto& w : s.Warnings)
    warnings->InsertNextValue(w);
  fd->AddArray(warnings);
}
} // namespace

vtkSTEPReader::vtkSTEPReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkSTEPReader::~vtkSTEPReader()
{
  this->SetFileName(nullptr);
}

int vtkSTEPReader::CanReadFile(const char* filename)
{
  try
  {
    brt::CheckStepFile(filename ? filename : "");
    return 1;
  }
  catch (const std::exception&)
  {
    return 0;
  }
}

int vtkSTEPReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* out)
{
  // Pieces (MPI ranks) get whole faces of the display mesh; the B-Rep in the field data is
  // complete in every piece, since each rank's samples may touch any face.
  out->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkSTEPReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out)
{
  vtkPolyData* output = vtkPolyData::GetData(out, 0);
  output->Initialize();
  brt::ConversionOptions options;
  options.Tolerance = this->Tolerance;
  options.Heal = this->Heal;
  options.LinearDeflection = this->LinearDeflection;
  options.AngularDeflection = this->AngularDeflection;
  options.MaxEdgeLength = this->MaxEdgeLength;
  options.DelaunayRefinement = this->DelaunayRefinement;
  options.Progress = [this](double f) {
    this->UpdateProgress(f);
    return !this->GetAbortExecute();
  };
  brt::BRepModel model;
  try
  {
    brt::IsolationOptions isolation;
    isolation.TimeLimit = this->TimeLimit;
    model = brt::ConvertStepFileIsolated(this->FileName ? this->FileName : "", options, isolation);
  }
  catch (const std::exception& e)
  {
    // One message naming the file and the reason; the output stays empty, so nothing partial
    // reaches downstream filters (returning 0 would add the executive's generic error).
    vtkErrorMacro(<< e.what());
    output->Initialize();
    return 1;
  }
  vtkInformation* outInfo = out->GetInformationObject(0);
  const int piece = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    : 0;
  const int pieces = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 1;
  FillPolyData(model, output, piece, pieces);

  const auto& s = model.Stats;
  vtkLogF(INFO,
    "vtkSTEPReader: %s: %d solids, %d faces, %d patches (max deviation %.2e, tolerance %.1e), "
    "%d trimming segments in %d loops (max gap before welding %.2e UV), %d edges, %zu mesh "
    "points; read %.3f s, heal %.3f s, convert %.3f s, mesh %.3f s",
    model.SourceFile.c_str(), s.Solids, s.Faces, s.Patches, s.MaxPatchDeviation, model.Tolerance,
    s.TrimSegments, s.Loops, s.MaxLoopGap, s.Edges, model.Mesh.NumberOfPoints(), s.ReadSeconds,
    s.HealSeconds, s.ConvertSeconds, s.MeshSeconds);
  const size_t shown = std::min<size_t>(s.Warnings.size(), 20);
  for (size_t i = 0; i < shown; ++i)
    vtkWarningMacro(<< this->FileName << ": " << s.Warnings[i]);
  if (s.Warnings.size() > shown)
    vtkWarningMacro(<< this->FileName << ": " << s.Warnings.size() - shown
                    << " more warnings in the ConversionWarnings field array");
  return 1;
}

void vtkSTEPReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "Heal: " << this->Heal << "\n";
  os << indent << "LinearDeflection: " << this->LinearDeflection << "\n";
  os << indent << "AngularDeflection: " << this->AngularDeflection << "\n";
  os << indent << "MaxEdgeLength: " << this->MaxEdgeLength << "\n";
  os << indent << "DelaunayRefinement: " << this->DelaunayRefinement << "\n";
  os << indent << "TimeLimit: " << this->TimeLimit << "\n";
}
