#include "BRepFieldData.h"

#include "Midsurface.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <cmath>
#include <string>
#include <vector>

namespace brt
{
namespace
{
[[noreturn]] void Fail(const std::string& what)
{
  throw ContractError("input is not a BRepThickness B-Rep (docs/DataContract.md): " + what);
}

/// Array `name` of field or point data with `comps` components; null if it is absent and not
/// required.
vtkDataArray* Checked(vtkFieldData* fd, const char* name, int comps, bool required = true)
{
  vtkDataArray* a = fd->GetArray(name);
  if (!a)
  {
    if (required)
      Fail(std::string("no array '") + name + "'");
    return nullptr;
  }
  if (a->GetNumberOfComponents() != comps)
    Fail(std::string("array '") + name + "' has " + std::to_string(a->GetNumberOfComponents()) +
      " components, expected " + std::to_string(comps));
  return a;
}

/// Array `name` with `comps` components from field or point data, as doubles (tuple-major).
/// `rows` < 0: any number of tuples; else exactly that many.
std::vector<double> Get(vtkFieldData* fd, const char* name, int comps, vtkIdType rows = -1,
  bool required = true)
{
  vtkDataArray* a = Checked(fd, name, comps, required);
  if (!a)
    return {};
  if (rows >= 0 && a->GetNumberOfTuples() != rows)
    Fail(std::string("array '") + name + "' has " + std::to_string(a->GetNumberOfTuples()) +
      " tuples, expected " + std::to_string(rows));
  std::vector<double> v(static_cast<size_t>(a->GetNumberOfTuples()) * comps);
  // The reader's arrays are doubles: copied whole (a tuple at a time, a virtual call each, was
  // most of reading the model).
  if (auto* d = vtkDoubleArray::FastDownCast(a))
    std::copy(d->GetPointer(0), d->GetPointer(0) + v.size(), v.begin());
  else
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
      a->GetTuple(i, &v[static_cast<size_t>(i) * comps]);
  for (double x : v)
    if (!std::isfinite(x))
      Fail(std::string("array '") + name + "' holds a value that is not finite");
  return v;
}

vtkIdType Rows(vtkFieldData* fd, const char* name, int comps)
{
  return Checked(fd, name, comps)->GetNumberOfTuples();
}

int Index(double value, int lo, int hi, const char* what, size_t row)
{
  const int i = static_cast<int>(value);
  if (value != i || i < lo || i >= hi)
    Fail(std::string(what) + " of row " + std::to_string(row) + " is " + std::to_string(value) +
      ", outside [" + std::to_string(lo) + ", " + std::to_string(hi) + ")");
  return i;
}

void Range(int first, int count, int size, const char* what, size_t row)
{
  if (first < 0 || count < 0 || first + count > size)
    Fail(std::string(what) + " of row " + std::to_string(row) + " covers [" +
      std::to_string(first) + ", " + std::to_string(first + count) + "), outside [0, " +
      std::to_string(size) + ")");
}
} // namespace

bool HasBRepFieldData(vtkPolyData* input)
{
  return input && input->GetFieldData() && input->GetFieldData()->GetArray("BezierPatches");
}

BRepModel ModelFromPolyData(vtkPolyData* input)
{
  BRepModel m;
  vtkFieldData* fd = input->GetFieldData();
  if (!HasBRepFieldData(input))
    Fail("no field array 'BezierPatches' (connect the STEP reader's output)");

  const vtkIdType np = Rows(fd, "BezierPatches", 48);
  const vtkIdType nf = Rows(fd, "FaceInfo", 9);
  const vtkIdType nl = Rows(fd, "TrimLoops", 4);
  const vtkIdType ns = Rows(fd, "TrimSegments", 8);
  const vtkIdType ne = Rows(fd, "EdgeInfo", 4);
  const vtkIdType nes = Rows(fd, "EdgeSegments", 12);
  const int NF = static_cast<int>(nf), NP = static_cast<int>(np), NL = static_cast<int>(nl),
            NS = static_cast<int>(ns), NE = static_cast<int>(ne), NES = static_cast<int>(nes);

  const auto tol = Get(fd, "Tolerance", 1, 1);
  m.Tolerance = tol[0];
  if (auto* unit = vtkStringArray::SafeDownCast(fd->GetAbstractArray("LengthUnit")))
    if (unit->GetNumberOfValues() > 0)
      m.LengthUnit = unit->GetValue(0);
  if (auto* src = vtkStringArray::SafeDownCast(fd->GetAbstractArray("SourceFile")))
    if (src->GetNumberOfValues() > 0)
      m.SourceFile = src->GetValue(0);

  // Faces.
  const auto info = Get(fd, "FaceInfo", 9, nf);
  const auto domain = Get(fd, "FaceDomain", 4, nf);
  const auto period = Get(fd, "FacePeriod", 2, nf);
  const auto uvTol = Get(fd, "FaceUVTolerance", 1, nf);
  const auto dev = Get(fd, "FaceMaxDeviation", 1, nf, false);
  // Optional: without it (a file saved before it existed) no face counts as its patches (the
  // certification then keeps its margins on O's own face, brt::PatchesAreTheSurface).
  const auto degrees = Get(fd, "FaceDegrees", 2, nf, false);
  m.Faces.resize(NF);
  for (int f = 0; f < NF; ++f)
  {
    Face& F = m.Faces[f];
    const double* I = &info[9 * f];
    F.Solid = static_cast<int>(I[0]);
    F.Reversed = I[1] != 0.0;
    F.Kind = static_cast<SurfaceKind>(Index(I[2], 0, static_cast<int>(SurfaceKind::Other) + 1,
      "FaceInfo surface kind", f));
    F.FirstPatch = static_cast<int>(I[3]);
    F.PatchesU = static_cast<int>(I[4]);
    F.PatchesV = static_cast<int>(I[5]);
    if (F.PatchesU < 0 || F.PatchesV < 0 || (F.PatchesU == 0) != (F.PatchesV == 0))
      Fail("FaceInfo patch grid of row " + std::to_string(f) + " is " +
        std::to_string(F.PatchesU) + " x " + std::to_string(F.PatchesV));
    F.PatchCount = F.PatchesU * F.PatchesV;
    Range(F.FirstPatch, F.PatchCount, NP, "FaceInfo patches", f);
    F.FirstLoop = static_cast<int>(I[6]);
    F.LoopCount = static_cast<int>(I[7]);
    Range(F.FirstLoop, F.LoopCount, NL, "FaceInfo loops", f);
    F.Rational = I[8] != 0.0;
    std::copy(&domain[4 * f], &domain[4 * f] + 4, F.Domain.begin());
    F.Period = { period[2 * f], period[2 * f + 1] };
    F.UVTolerance = uvTol[f];
    F.MaxDeviation = dev.empty() ? -1.0 : dev[f];
    if (!degrees.empty())
    {
      F.DegreeU = Index(degrees[2 * f], 0, 64, "FaceDegrees", f);
      F.DegreeV = Index(degrees[2 * f + 1], 0, 64, "FaceDegrees", f);
    }
  }
  // Optional: without it (a file saved before it existed) the solver keeps the patches' contacts.
  const auto exact = Get(fd, "FaceExactSurface", 8, nf, false);
  if (!exact.empty())
  {
    m.FaceExact.resize(NF);
    for (int f = 0; f < NF; ++f)
      std::copy(&exact[8 * f], &exact[8 * f] + 8, m.FaceExact[f].begin());
  }

  // Optional: where the file's faces and edges miss each other (the filter flags the samples
  // there, FailReason 12); none in a file saved before it existed.
  const auto loose = Get(fd, "LooseVertices", 4, -1, false);
  for (size_t i = 0; i + 3 < loose.size(); i += 4)
  {
    if (!(loose[i + 3] >= 0.0))
      Fail("array 'LooseVertices' has a negative radius in row " + std::to_string(i / 4));
    m.LooseVertices.push_back({ loose[i], loose[i + 1], loose[i + 2], loose[i + 3] });
  }
  const auto looseFaces = Get(fd, "LooseFaces", 1, -1, false);
  for (size_t i = 0; i < looseFaces.size(); ++i)
    m.LooseFaces.push_back(Index(looseFaces[i], 0, NF, "LooseFaces", i));
  const auto overlapping = Get(fd, "OverlappingFaces", 1, -1, false);
  for (size_t i = 0; i < overlapping.size(); ++i)
    m.OverlappingFaces.push_back(Index(overlapping[i], 0, NF, "OverlappingFaces", i));

  // Patches.
  const auto cps = Get(fd, "BezierPatches", 48, np);
  const auto pface = Get(fd, "PatchFace", 1, np);
  const auto pdom = Get(fd, "PatchDomain", 4, np);
  m.Patches.resize(NP);
  for (int p = 0; p < NP; ++p)
  {
    BezierPatch& P = m.Patches[p];
    std::copy(&cps[48 * p], &cps[48 * p] + 48, P.ControlPoints.begin());
    P.Face = Index(pface[p], 0, NF, "PatchFace", p);
    std::copy(&pdom[4 * p], &pdom[4 * p] + 4, P.Domain.begin());
    if (!(P.Domain[1] > P.Domain[0]) || !(P.Domain[3] > P.Domain[2]))
      Fail("PatchDomain of row " + std::to_string(p) + " is empty");
  }
  for (int f = 0; f < NF; ++f)
    for (int p = m.Faces[f].FirstPatch; p < m.Faces[f].FirstPatch + m.Faces[f].PatchCount; ++p)
      if (m.Patches[p].Face != f)
        Fail("patch " + std::to_string(p) + " is listed by face " + std::to_string(f) +
          " but PatchFace says " + std::to_string(m.Patches[p].Face));

  // Trimming loops and segments.
  const auto loops = Get(fd, "TrimLoops", 4, nl);
  m.Loops.resize(NL);
  for (int l = 0; l < NL; ++l)
  {
    TrimLoop& L = m.Loops[l];
    L.Face = Index(loops[4 * l], 0, NF, "TrimLoops face", l);
    L.FirstSegment = static_cast<int>(loops[4 * l + 1]);
    L.SegmentCount = static_cast<int>(loops[4 * l + 2]);
    Range(L.FirstSegment, L.SegmentCount, NS, "TrimLoops segments", l);
    L.Outer = loops[4 * l + 3] != 0.0;
  }
  const auto segs = Get(fd, "TrimSegments", 8, ns);
  const auto sinfo = Get(fd, "TrimSegmentInfo", 4, ns);
  const auto srange = Get(fd, "TrimSegmentRange", 2, ns);
  m.TrimSegments.resize(NS);
  for (int s = 0; s < NS; ++s)
  {
    TrimSegment& S = m.TrimSegments[s];
    std::copy(&segs[8 * s], &segs[8 * s] + 8, S.ControlPoints.begin());
    S.Face = Index(sinfo[4 * s], 0, NF, "TrimSegmentInfo face", s);
    S.Loop = Index(sinfo[4 * s + 1], 0, NL, "TrimSegmentInfo loop", s);
    S.Edge = Index(sinfo[4 * s + 2], -1, NE, "TrimSegmentInfo edge", s);
    S.Reversed = sinfo[4 * s + 3] != 0.0;
    S.T0 = srange[2 * s];
    S.T1 = srange[2 * s + 1];
  }

  // Edges and their 3D segments.
  const auto einfo = Get(fd, "EdgeInfo", 4, ne);
  const auto efaces = Get(fd, "EdgeFaces", 2, ne);
  const auto erange = Get(fd, "EdgeRange", 2, ne, false);
  const auto esegs = Get(fd, "EdgeSegments", 12, nes);
  const auto esedge = Get(fd, "EdgeSegmentEdge", 1, nes);
  const auto esrange = Get(fd, "EdgeSegmentRange", 2, nes);
  m.EdgeSegments.resize(NES);
  for (int s = 0; s < NES; ++s)
  {
    EdgeSegment& S = m.EdgeSegments[s];
    std::copy(&esegs[12 * s], &esegs[12 * s] + 12, S.ControlPoints.begin());
    S.Edge = Index(esedge[s], 0, NE, "EdgeSegmentEdge", s);
    S.T0 = esrange[2 * s];
    S.T1 = esrange[2 * s + 1];
    if (!(S.T1 > S.T0))
      Fail("EdgeSegmentRange of row " + std::to_string(s) + " is not ascending");
  }
  m.Edges.resize(NE);
  for (int e = 0; e < NE; ++e)
  {
    Edge& E = m.Edges[e];
    E.FirstSegment = static_cast<int>(einfo[4 * e]);
    E.SegmentCount = static_cast<int>(einfo[4 * e + 1]);
    Range(E.FirstSegment, E.SegmentCount, NES, "EdgeInfo segments", e);
    E.Seam = einfo[4 * e + 2] != 0.0;
    E.FaceCount = static_cast<int>(einfo[4 * e + 3]);
    E.Faces = { Index(efaces[2 * e], -1, NF, "EdgeFaces", e),
      Index(efaces[2 * e + 1], -1, NF, "EdgeFaces", e) };
    if (!erange.empty())
    {
      E.T0 = erange[2 * e];
      E.T1 = erange[2 * e + 1];
    }
    else if (E.SegmentCount > 0) // files written before EdgeRange: the segments cover the edge
    {
      E.T0 = m.EdgeSegments[E.FirstSegment].T0;
      E.T1 = m.EdgeSegments[E.FirstSegment + E.SegmentCount - 1].T1;
    }
  }

  // Display mesh: the points (samples) with their face, (u,v) and outward normal.
  vtkPointData* pd = input->GetPointData();
  const vtkIdType n = input->GetNumberOfPoints();
  const auto faceIds = Get(pd, "FaceId", 1, n);
  const auto uv = Get(pd, "FaceUV", 2, n);
  vtkDataArray* normals = pd->GetNormals() ? pd->GetNormals() : pd->GetArray("Normals");
  if (!normals || normals->GetNumberOfComponents() != 3)
    Fail("no point normals (3 components)");
  DisplayMesh& M = m.Mesh;
  M.FaceIds.resize(n);
  M.UV = uv;
  for (vtkIdType i = 0; i < n; ++i)
    M.FaceIds[i] = Index(faceIds[i], 0, NF, "point array FaceId", i);
  M.Points.resize(3 * n);
  vtkDataArray* points = input->GetPoints() ? input->GetPoints()->GetData() : nullptr;
  if (auto* d = vtkDoubleArray::FastDownCast(points))
    std::copy(d->GetPointer(0), d->GetPointer(0) + 3 * n, M.Points.begin());
  else
    for (vtkIdType i = 0; i < n; ++i)
      input->GetPoint(i, &M.Points[3 * i]);
  M.Normals.resize(3 * n);
  if (auto* d = vtkDoubleArray::FastDownCast(normals))
    std::copy(d->GetPointer(0), d->GetPointer(0) + 3 * n, M.Normals.begin());
  else
    for (vtkIdType i = 0; i < n; ++i)
      normals->GetTuple(i, &M.Normals[3 * i]);
  // The principal curvatures (the osculating bound), where the reader gave them.
  M.Curvatures.clear();
  if (vtkDataArray* c = pd->GetArray("PrincipalCurvatures"))
  {
    if (c->GetNumberOfComponents() != 2 || c->GetNumberOfTuples() != n)
      Fail("point array PrincipalCurvatures: 2 components per point expected");
    M.Curvatures.resize(2 * n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      c->GetTuple(i, &M.Curvatures[2 * i]);
      if (!std::isfinite(M.Curvatures[2 * i]) || !std::isfinite(M.Curvatures[2 * i + 1]))
        Fail("point array PrincipalCurvatures: a value that is not finite at point " +
          std::to_string(i));
    }
  }
  if (input->GetNumberOfVerts() + input->GetNumberOfLines() + input->GetNumberOfStrips() > 0)
    Fail("the display mesh has vertices, lines or strips; only triangles are expected");
  // The triangles from the cell array's offsets and connectivity (cell by cell through an id
  // list was a third of reading the model).
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nc = polys->GetNumberOfCells();
  M.Triangles.resize(static_cast<size_t>(3 * nc));
  M.TriangleFace.resize(static_cast<size_t>(nc));
  auto triangles = [&](auto* offsets, auto* connectivity) {
    for (vtkIdType c = 0; c < nc; ++c)
    {
      const vtkIdType begin = offsets->GetValue(c), size = offsets->GetValue(c + 1) - begin;
      if (size != 3)
        Fail("the display mesh has a polygon with " + std::to_string(size) +
          " vertices; only triangles are expected");
      int f = -1;
      for (int k = 0; k < 3; ++k)
      {
        const vtkIdType id = connectivity->GetValue(begin + k);
        if (id < 0 || id >= n)
          Fail("a triangle names point " + std::to_string(id) + " of " + std::to_string(n));
        M.Triangles[static_cast<size_t>(3 * c + k)] = static_cast<int>(id);
        if (k == 0)
          f = M.FaceIds[id];
        else if (M.FaceIds[id] != f)
          Fail("a triangle joins vertices of different faces");
      }
      M.TriangleFace[static_cast<size_t>(c)] = f;
    }
  };
  if (polys->IsStorage64Bit())
    triangles(polys->GetOffsetsArray64(), polys->GetConnectivityArray64());
  else
    triangles(polys->GetOffsetsArray32(), polys->GetConnectivityArray32());

  m.Stats.Faces = NF;
  m.Stats.Patches = NP;
  m.Stats.Loops = NL;
  m.Stats.TrimSegments = NS;
  m.Stats.Edges = NE;
  m.Stats.EdgeSegments = NES;
  return m;
}

namespace
{
template <typename T>
void CopyArray(vtkDataArray* a, std::vector<T>& out)
{
  const vtkIdType n = a->GetNumberOfTuples();
  const int c = a->GetNumberOfComponents();
  out.resize(static_cast<size_t>(n * c));
  for (vtkIdType i = 0; i < n; ++i)
    for (int k = 0; k < c; ++k)
      out[static_cast<size_t>(i * c + k)] = static_cast<T>(a->GetComponent(i, k));
}
} // namespace

bool BRepMidsurfaceInput(vtkPolyData* input, MidsurfaceInput& in, std::string& missing)
{
  vtkPointData* pd = input->GetPointData();
  for (const char* name : { "FaceId", "Normals", "Thickness", "ContactType", "OppositeFaceId",
         "ContactAngle", "EdgeZone" })
    if (!pd->GetArray(name))
    {
      missing = name;
      return false;
    }
  const vtkIdType nP = input->GetNumberOfPoints();
  in.Points.resize(static_cast<size_t>(3 * nP));
  for (vtkIdType i = 0; i < nP; ++i)
    input->GetPoint(i, &in.Points[static_cast<size_t>(3 * i)]);
  CopyArray(pd->GetArray("Normals"), in.Normals);
  CopyArray(pd->GetArray("FaceId"), in.FaceIds);
  CopyArray(pd->GetArray("Thickness"), in.Thickness);
  CopyArray(pd->GetArray("ContactType"), in.ContactType);
  CopyArray(pd->GetArray("OppositeFaceId"), in.OppositeFace);
  CopyArray(pd->GetArray("ContactAngle"), in.ContactAngle);
  CopyArray(pd->GetArray("EdgeZone"), in.EdgeZone);
  in.Triangles.clear();
  vtkCellArray* polys = input->GetPolys();
  vtkNew<vtkIdList> ids;
  for (polys->InitTraversal(); polys->GetNextCell(ids);)
    if (ids->GetNumberOfIds() == 3)
      for (int k = 0; k < 3; ++k)
        in.Triangles.push_back(static_cast<int>(ids->GetId(k)));
  return true;
}

} // namespace brt
