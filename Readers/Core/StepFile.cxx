#include "StepFile.h"
#include "StepScan.h"

#include <APIHeaderSection_MakeHeader.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Check.hxx>
#include <TCollection_HAsciiString.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <StepData_StepModel.hxx>
#include <StepShape_ManifoldSolidBrep.hxx>
#include <BRep_Builder.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <Transfer_TransientProcess.hxx>
#include <TransferBRep.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS_Shape.hxx>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <map>
#include <sys/stat.h>
#include <vector>

namespace brt
{
namespace
{
[[noreturn]] void Fail(const std::string& path, const std::string& reason)
{
  throw InputError("STEP file '" + path + "': " + reason);
}

std::string Upper(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

std::string Count(long n, const char* one, const char* many)
{
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string NameList(const std::vector<std::string>& names)
{
  std::string list;
  for (size_t i = 0; i < names.size() && i < 3; ++i)
    list += (i ? ", " : "") + names[i];
  if (names.size() > 3)
    list += " and " + std::to_string(names.size() - 3) + " more";
  return list;
}

/// Why a file that OpenCASCADE read gave no B-Rep face, where the file says: its shapes are
/// triangles only (AP242's tessellated geometry: a mesh, not the exact faces this tool measures),
/// or its parts lie in other files that it names (an assembly of external references). Empty
/// where neither.
std::string WhyNoBRep(const StepScanResult& scan)
{
  // Constructive solid geometry, whatever faces the file also declares: none was transferred.
  for (const char* csg : { "CSG_SOLID", "BOOLEAN_RESULT", "CSG_SHAPE_REPRESENTATION" })
    for (const auto& entry : scan.TypeNames)
      if (entry.second == csg)
        return std::string("holds constructive solid geometry (") + csg + ": Booleans of "
          "primitives, which OpenCASCADE does not read) and no B-Rep faces it could transfer: "
          "export the model as a B-Rep";
  if (scan.DeclaredFaces > 0)
    return std::string();
  long triangulated = 0, tessellated = 0;
  for (const auto& entry : scan.TypeNames)
  {
    const std::string& t = entry.second;
    if (t == "TRIANGULATED_FACE" || t == "COMPLEX_TRIANGULATED_FACE" ||
      t == "TRIANGULATED_SURFACE_SET" || t == "COMPLEX_TRIANGULATED_SURFACE_SET")
      ++triangulated;
    else if (t == "TESSELLATED_SOLID" || t == "TESSELLATED_SHELL")
      ++tessellated;
  }
  if (triangulated > 0)
    return "holds only tessellated geometry (" +
      Count(triangulated, "triangulated face", "triangulated faces") +
      (tessellated > 0
          ? " in " + Count(tessellated, "tessellated solid or shell", "tessellated solids or shells")
          : std::string()) +
      ", AP242's meshes) and no B-Rep faces: the thickness is measured on the exact faces; "
      "export the model with its B-Rep solids (AP203, AP214, or AP242 with B-Rep)";
  if (!scan.ExternalFiles.empty())
    return "is an assembly whose parts lie in other files that it names (" +
      NameList(scan.ExternalFiles) +
      ") and holds no B-Rep faces itself: open each part's own file, or export the assembly as "
      "one file";
  for (const auto& entry : scan.TypeNames)
    if (entry.second == "DRAUGHTING_MODEL")
      return "holds a drawing (a draughting model of 2D views) and no B-Rep faces: nothing to "
        "measure; export the 3D model";

  return std::string();
}

/// Silences OpenCASCADE's default console printers while alive (the STEP parser prints every
/// syntax error it meets; we report one clear message instead).
class QuietMessenger
{
public:
  QuietMessenger()
  {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    for (Message_SequenceOfPrinters::Iterator it(m->Printers()); it.More(); it.Next())
      this->Saved.push_back(it.Value());
    m->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  }
  ~QuietMessenger()
  {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    for (const auto& p : this->Saved)
    {
      if (p->IsKind(STANDARD_TYPE(Message_PrinterOStream)))
        m->AddPrinter(p);
    }
  }
  QuietMessenger(const QuietMessenger&) = delete;
  QuietMessenger& operator=(const QuietMessenger&) = delete;

private:
  std::vector<Handle(Message_Printer)> Saved;
};
/// The solids one declared solid (a MANIFOLD_SOLID_BREP or BREP_WITH_VOIDS) became. OpenCASCADE's
/// transfer heals a shell that holds bodies sharing no edge into one solid per body; the file
/// said they are one. Each such group, per placement, is put back into one solid whose shell
/// holds all their faces, so that bodies touching face to face are joined as one
/// (JoinBodiesTouchingFaceToFace, run before the healing, which splits the ones that do not touch
/// again). The shape is returned as it was where no declared solid was split, else as a flat
/// compound of its solids, shells and faces.
TopoDS_Shape RegroupSplitSolids(const TopoDS_Shape& shape, STEPControl_Reader& reader,
  const Handle(StepData_StepModel)& model, int& regrouped)
{
  regrouped = 0;
  if (model.IsNull() || reader.WS().IsNull() || reader.WS()->TransferReader().IsNull())
    return shape;
  const Handle(Transfer_TransientProcess) tp = reader.WS()->TransferReader()->TransientProcess();
  if (tp.IsNull())
    return shape;
  std::map<const TopoDS_TShape*, int> groupOf;
  int groups = 0;
  for (int i = 1; i <= model->NbEntities(); ++i)
  {
    if (!model->Value(i)->IsKind(STANDARD_TYPE(StepShape_ManifoldSolidBrep)))
      continue;
    const TopoDS_Shape made = TransferBRep::ShapeResult(tp, model->Value(i));
    if (made.IsNull())
      continue;
    std::vector<const TopoDS_TShape*> solids;
    for (TopExp_Explorer x(made, TopAbs_SOLID); x.More(); x.Next())
      solids.push_back(x.Current().TShape().get());
    if (solids.size() < 2)
      continue;
    for (const TopoDS_TShape* t : solids)
      groupOf[t] = groups;
    ++groups;
  }
  if (groups == 0)
    return shape;
  // Per group and placement, the solids (their orientation and location composed).
  struct Bucket
  {
    int Group;
    TopLoc_Location Placement;
    std::vector<TopoDS_Shape> Members;
  };
  std::vector<Bucket> buckets;
  BRep_Builder builder;
  TopoDS_Compound out;
  builder.MakeCompound(out);
  for (TopExp_Explorer x(shape, TopAbs_SOLID); x.More(); x.Next())
  {
    const auto g = groupOf.find(x.Current().TShape().get());
    if (g == groupOf.end())
    {
      builder.Add(out, x.Current());
      continue;
    }
    auto b = std::find_if(buckets.begin(), buckets.end(), [&](const Bucket& k) {
      return k.Group == g->second && k.Placement.IsEqual(x.Current().Location());
    });
    if (b == buckets.end())
    {
      buckets.push_back(Bucket{ g->second, x.Current().Location(), {} });
      b = buckets.end() - 1;
    }
    b->Members.push_back(x.Current());
  }
  for (const Bucket& b : buckets)
  {
    if (b.Members.size() < 2)
    {
      builder.Add(out, b.Members[0]);
      continue;
    }
    TopoDS_Shell shell;
    builder.MakeShell(shell);
    for (const TopoDS_Shape& m : b.Members)
      for (TopExp_Explorer f(m, TopAbs_FACE); f.More(); f.Next())
        builder.Add(shell, f.Current());
    TopoDS_Solid solid;
    builder.MakeSolid(solid);
    builder.Add(solid, shell);
    builder.Add(out, solid);
    ++regrouped;
  }
  for (TopExp_Explorer x(shape, TopAbs_SHELL, TopAbs_SOLID); x.More(); x.Next())
    builder.Add(out, x.Current());
  for (TopExp_Explorer x(shape, TopAbs_FACE, TopAbs_SHELL); x.More(); x.Next())
    builder.Add(out, x.Current());
  return regrouped > 0 ? TopoDS_Shape(out) : shape;
}
} // namespace

void CheckStepFile(const std::string& path)
{
  if (path.empty())
  {
    throw InputError("STEP reader: no file name given");
  }
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0)
  {
    Fail(path, errno == ENOENT ? "file does not exist" : std::string(std::strerror(errno)));
  }
  if (S_ISDIR(st.st_mode))
  {
    Fail(path, "is a directory, not a file");
  }
  if (!S_ISREG(st.st_mode))
  {
    Fail(path, "is not a regular file");
  }
  if (st.st_size == 0)
  {
    Fail(path, "file is empty");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    Fail(path, std::string("cannot be opened: ") + std::strerror(errno));
  }
  constexpr std::streamoff window = 4096;
  std::string head(static_cast<size_t>(std::min<std::streamoff>(window, st.st_size)), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (head.find('\0') != std::string::npos)
  {
    Fail(path, "is not a STEP file: it holds binary data (NUL bytes) where the ISO-10303-21 "
               "header should be");
  }
  // Skip a UTF-8 byte-order mark, leading white space and comments (ISO 10303-21 lets a comment
  // stand wherever white space may, and OpenCASCADE's parser reads a file that opens with one:
  // the dodgy-step-files fixtures Gn002 and N010 do).
  size_t start = head.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  for (;;)
  {
    while (start < head.size() && std::isspace(static_cast<unsigned char>(head[start])))
      ++start;
    if (head.compare(start, 2, "/*") != 0)
      break;
    const size_t end = head.find("*/", start + 2);
    if (end == std::string::npos)
      break; // (a comment longer than the window: refused below)
    start = end + 2;
  }
  if (Upper(head.substr(start, 12)) != "ISO-10303-21")
  {
    Fail(path, "is not a STEP file: it does not start with the ISO-10303-21 header");
  }
  const std::streamoff tailSize = std::min<std::streamoff>(window, st.st_size);
  std::string tail(static_cast<size_t>(tailSize), '\0');
  in.seekg(st.st_size - tailSize);
  in.read(tail.data(), tailSize);
  if (Upper(tail).find("END-ISO-10303-21") == std::string::npos)
  {
    Fail(path, "is truncated or damaged: the END-ISO-10303-21 terminator is missing at its end");
  }
}

TopoDS_Shape ReadStepFile(const std::string& path, StepReadResult* info)
{
  const auto t0 = std::chrono::steady_clock::now();
  CheckStepFile(path);
  StepReadResult result;
  int drawingViews = 0; // a drawing's 2D views OpenCASCADE does not read, passed (below)
  result.Scan = ScanStepFile(path);
  QuietMessenger quiet;
  STEPControl_Reader reader;
  TopoDS_Shape shape;
  try
  {
    const IFSelect_ReturnStatus status = reader.ReadFile(path.c_str());
    if (status != IFSelect_RetDone)
    {
      Fail(path, "the STEP parser rejected it (syntax or schema error)");
    }
    Handle(StepData_StepModel) model = reader.StepModel();
    if (!model.IsNull())
    {
      // An entity OpenCASCADE could not read (a type it does not know, damaged parameters)
      // that the geometry refers to: its transfer would dereference nothing.
      for (int i = 1; i <= model->NbEntities(); ++i)
      {
        if (!model->IsErrorEntity(i) && !model->IsUnknownEntity(i))
        {
          continue;
        }
        // An entity of a known type whose only faults are text parameters that are not quoted
        // strings (a name or description left unset, $): OpenCASCADE builds it without that text,
        // and the geometry does not read it (AnalysisSitus's flipping joystick assembly writes
        // its transformations' names so).
        // So does a SEAM_CURVE that lists one pcurve for both sides of its seam (a 1997
        // Euclid-Quantum export, two of OpenCASCADE's own sample files): read as written, and
        // the healing gives the seam its second pcurve, a period along.
        if (!model->IsUnknownEntity(i))
        {
          bool onlyText = true;
          int fails = 0;
          for (const bool syntactic : { true, false })
          {
            const Handle(Interface_Check) check = model->Check(i, syntactic);
            for (int k = 1; !check.IsNull() && k <= check->NbFails(); ++k)
            {
              ++fails;
              onlyText = onlyText &&
                (std::strstr(check->CFail(k), "not a quoted String") != nullptr ||
                  std::strstr(check->CFail(k), "Seam Curve with twice the same geom") != nullptr);
            }
          }
          if (fails > 0 && onlyText)
          {
            continue;
          }
        }
        const long id = model->IdentLabel(model->Value(i));
        // A drawing's view: a REPRESENTATION_MAP whose mapped representation is a 2D one that
        // OpenCASCADE does not read (CAx-IF's drawing files map their
        // GEOMETRICALLY_BOUNDED_2D_WIREFRAME_REPRESENTATIONs into draughting models beside the
        // part's solid). No 3D geometry hangs on it: passed, and the views warned of.
        {
          const auto map = result.Scan.MappedRepresentations.find(id);
          const auto mapped = map != result.Scan.MappedRepresentations.end()
            ? result.Scan.TypeNames.find(map->second)
            : result.Scan.TypeNames.end();
          if (mapped != result.Scan.TypeNames.end() &&
            mapped->second.find("2D") != std::string::npos &&
            mapped->second.find("REPRESENTATION") != std::string::npos)
          {
            ++drawingViews;
            continue;
          }
        }
        const auto target = result.Scan.GeometryTargets.find(id);
        if (target == result.Scan.GeometryTargets.end())
        {
          continue;
        }
        auto typeOf = [&](long e) {
          const auto t = result.Scan.TypeNames.find(e);
          const std::string name = t != result.Scan.TypeNames.end() ? t->second : "?";
          return "#" + std::to_string(e) + (name[0] == '(' ? " " + name : " (" + name + ")");
        };
        // A file with no face to measure says what it holds instead (a drawing's 2D views are
        // what OpenCASCADE fails on in CAx-IF's drawing files).
        const std::string why = WhyNoBRep(result.Scan);
        if (!why.empty())
          Fail(path, why);
        Fail(path, "entity " + typeOf(id) + " is damaged or of a type OpenCASCADE does not "
          "read, and " + typeOf(target->second) + " refers to it");
      }
      APIHeaderSection_MakeHeader header(model);
      if (header.IsDone() && header.NbSchemaIdentifiers() > 0)
      {
        result.Schema = header.SchemaIdentifiersValue(1)->ToCString();
      }
    }
    result.Roots = reader.NbRootsForTransfer();
    if (result.Roots > 0)
    {
      reader.TransferRoots();
    }
    TopoDS_Shape fromRoots = reader.NbShapes() > 0 ? reader.OneShape() : TopoDS_Shape();
    const bool rootsGaveSolid =
      !fromRoots.IsNull() && TopExp_Explorer(fromRoots, TopAbs_SOLID).More();
    if (!rootsGaveSolid && result.Scan.DeclaredSolids > 0 && !model.IsNull())
    {
      // The product structure led to no solid (OpenCASCADE 7.6 with some AP242 files): take
      // the solid entities themselves.
      reader.ClearShapes();
      for (int i = 1; i <= model->NbEntities(); ++i)
      {
        if (model->Value(i)->IsKind(STANDARD_TYPE(StepShape_ManifoldSolidBrep)) &&
          reader.TransferOne(i))
        {
          ++result.SolidsTransferredDirectly;
        }
      }
      if (result.SolidsTransferredDirectly == 0)
      {
        reader.ClearShapes();
        if (result.Roots > 0)
        {
          reader.TransferRoots();
        }
      }
      else
      {
        result.Warnings.push_back("the file's product structure gave no solid; its " +
          std::to_string(result.SolidsTransferredDirectly) +
          " solid entities were read directly (placements of assembly instances are lost)");
      }
    }
    else if (result.Roots == 0)
    {
      const std::string why = WhyNoBRep(result.Scan);
      Fail(path, why.empty()
          ? "holds no shape that can be transferred (no product, solid, shell or face)"
          : why);
    }
    if (reader.NbShapes() == 0)
    {
      const std::string why = WhyNoBRep(result.Scan);
      Fail(path, why.empty() ? "holds no geometry that OpenCASCADE could transfer" : why);
    }
    shape = reader.OneShape();
    int regrouped = 0;
    shape = RegroupSplitSolids(shape, reader, model, regrouped);
    result.RegroupedSolids = regrouped;
  }
  catch (const InputError&)
  {
    throw;
  }
  catch (const Standard_Failure& e)
  {
    Fail(path, std::string("OpenCASCADE failed while reading it: ") + e.GetMessageString() +
        DescribeUnreadGeometry(result.Scan));
  }
  if (shape.IsNull() || !TopExp_Explorer(shape, TopAbs_FACE).More())
  {
    const std::string why = WhyNoBRep(result.Scan);
    if (!why.empty())
      Fail(path, why);
    Fail(path, "holds no solid, shell or face (only curves, points or nothing): there is no "
               "wall to measure" + DescribeUnreadGeometry(result.Scan));
  }
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  result.Faces = faces.Extent();
  const StepScanResult& scan = result.Scan;
  if (result.SolidsTransferredDirectly == 0 && result.Faces < scan.DeclaredFaces)
  {
    // An assembly places one part several times: its faces count once per instance, so
    // fewer faces than declared means lost ones.
    result.Warnings.push_back("the file declares " + std::to_string(scan.DeclaredFaces) +
      " faces but only " + std::to_string(result.Faces) + " were transferred: " +
      std::to_string(scan.DeclaredFaces - result.Faces) + " faces were lost (damaged or "
      "unsupported geometry); the solids they bound may be open");
  }
  result.Warnings.insert(result.Warnings.end(), scan.Warnings.begin(), scan.Warnings.end());
  TopTools_IndexedMapOfShape solids;
  TopExp::MapShapes(shape, TopAbs_SOLID, solids);
  if (result.SolidsTransferredDirectly == 0 && solids.Extent() < scan.DeclaredSolids)
  {
    result.Warnings.push_back("the file declares " + std::to_string(scan.DeclaredSolids) +
      " solids but only " + std::to_string(solids.Extent()) + " were transferred");
  }
  if (drawingViews > 0)
  {
    result.Warnings.push_back("the file holds a drawing (" + std::to_string(drawingViews) +
      " 2D view(s) in draughting models) that is not read: only its 3D geometry is measured");
  }
  // Parts the file leaves to other files (an assembly of external references): not read.
  if (!scan.ExternalFiles.empty())
  {
    result.Warnings.push_back("the file names other STEP files as the sources of parts (" +
      NameList(scan.ExternalFiles) + "): those parts are not read, only the geometry in this file");
  }
  if (scan.SurfaceModels > 0)
  {
    result.Warnings.push_back("the file holds " + std::to_string(scan.SurfaceModels) +
      " surface model(s) (SHELL_BASED_SURFACE_MODEL): shells, not solids; a closed shell is "
      "measured as the solid it bounds, an open one is not");
  }
  result.Seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (info)
  {
    *info = result;
  }
  return shape;
}

} // namespace brt
