// Bad input: each case gives one clear InputError naming the file and the reason, quickly.
#include "TestHelpers.h"

#include "StepFile.h"

#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Writer.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Pnt.hxx>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace
{
using namespace brt;

fs::path TempDir()
{
  static const fs::path dir = test::TempDir("brt-bad-input");
  return dir;
}

using test::ReadAll;

void Write(const fs::path& p, const std::string& text)
{
  std::ofstream(p, std::ios::binary) << text;
}

/// Converting `path` throws an InputError naming the file and containing `reason`.
void ExpectError(const std::string& path, const std::string& reason)
{
  const auto t0 = std::chrono::steady_clock::now();
  try
  {
    (void)ConvertStepFile(path, ConversionOptions());
    ADD_FAILURE() << "no error for " << path;
  }
  catch (const InputError& e)
  {
    const std::string msg = e.what();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("[bad input] %.3f s: %s\n", s, msg.c_str());
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(reason), std::string::npos) << msg;
  }
}

TEST(BadInput, MissingFile)
{
  ExpectError((TempDir() / "no-such-file.step").string(), "does not exist");
}

TEST(BadInput, EmptyFile)
{
  const fs::path p = TempDir() / "empty.step";
  Write(p, "");
  ExpectError(p.string(), "empty");
}

TEST(BadInput, TextFileThatIsNotStep)
{
  const fs::path p = TempDir() / "notes.step";
  Write(p, "This is a shopping list, not a STEP file.\nmilk\neggs\n");
  ExpectError(p.string(), "does not start with the ISO-10303-21 header");
}

TEST(BadInput, TruncatedStep)
{
  const std::string full = ReadAll(test::DataFile("l_bracket.step"));
  ASSERT_GT(full.size(), 1000u);
  const fs::path p = TempDir() / "truncated.step";
  Write(p, full.substr(0, full.size() / 2));
  ExpectError(p.string(), "truncated");
}

TEST(BadInput, CurvesButNoSolidOrFace)
{
  const fs::path p = TempDir() / "curves-only.step";
  STEPControl_Writer writer;
  ASSERT_EQ(writer.Transfer(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(10, 0, 0)).Edge(),
              STEPControl_AsIs),
    IFSelect_RetDone);
  ASSERT_EQ(writer.Write(p.string().c_str()), IFSelect_RetDone);
  ExpectError(p.string(), "no solid, shell or face");
}

/// A small AP242 file of one product whose shape is `representation` (entity #9, with any other
/// entities it needs), in millimetres.
std::string OnePartFile(const std::string& representation)
{
  return R"(ISO-10303-21;
HEADER;
FILE_DESCRIPTION((''),'2;1');
FILE_NAME('part.step','2026-12-05T00:00:00',(''),(''),'','','');
FILE_SCHEMA(('AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF { 1 0 10303 442 1 1 4 }'));
ENDSEC;
DATA;
#1=APPLICATION_CONTEXT('managed model based 3d engineering');
#2=PRODUCT_CONTEXT('',#1,'mechanical');
#3=PRODUCT('part','part','',(#2));
#4=PRODUCT_DEFINITION_FORMATION('','',#3);
#5=PRODUCT_DEFINITION_CONTEXT('part definition',#1,'design');
#6=PRODUCT_DEFINITION('design','',#4,#5);
#7=PRODUCT_DEFINITION_SHAPE('','',#6);
#8=SHAPE_DEFINITION_REPRESENTATION(#7,#9);
)" + representation + R"(
#20=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#24)) GLOBAL_UNIT_ASSIGNED_CONTEXT((#21,#22,#23)) REPRESENTATION_CONTEXT('',''));
#21=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));
#22=(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.));
#23=(NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT());
#24=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#21,'distance_accuracy_value','');
ENDSEC;
END-ISO-10303-21;
)";
}

// A part that is a mesh only (a TESSELLATED_SOLID of TRIANGULATED_FACEs, as CATIA and NIST's test
// cases write them): OpenCASCADE 7.6 transfers nothing, and the error says why.
TEST(BadInput, TessellatedGeometryOnly)
{
  const fs::path p = TempDir() / "tessellated-only.step";
  Write(p, OnePartFile(R"(#9=TESSELLATED_SHAPE_REPRESENTATION('',(#10),#20);
#10=TESSELLATED_SOLID('',(#11),$);
#11=TRIANGULATED_FACE('',#12,4,((0.,0.,-1.)),$,(1,2,3,4),((1,3,2),(1,2,4),(2,3,4),(3,1,4)));
#12=COORDINATES_LIST('',4,((0.,0.,0.),(10.,0.,0.),(0.,10.,0.),(0.,0.,10.)));)"));
  ExpectError(p.string(), "holds only tessellated geometry (1 triangulated face in 1 tessellated "
                          "solid or shell, AP242's meshes) and no B-Rep faces");
}

// An assembly whose parts lie in other files (EXTERNAL_SOURCE or DOCUMENT_FILE names them, as
// CAx-IF's external reference test files do; a document's file name may come third): an error
// naming them where the file holds no face itself, a warning where it holds some.
TEST(BadInput, AssemblyOfExternalFiles)
{
  const fs::path p = TempDir() / "external-assembly.step";
  Write(p, OnePartFile(R"(#9=SHAPE_REPRESENTATION('',(#13),#20);
#13=AXIS2_PLACEMENT_3D('',#14,#15,#16);
#14=CARTESIAN_POINT('',(0.,0.,0.));
#15=DIRECTION('',(0.,0.,1.));
#16=DIRECTION('',(1.,0.,0.));
#30=EXTERNAL_SOURCE(IDENTIFIER('bracket.stp'));
#31=EXTERNAL_SOURCE(IDENTIFIER('bolt.step'));
#32=DOCUMENT_FILE('','','nut_prt.stp','nut',$,$);)"));
  ExpectError(p.string(), "is an assembly whose parts lie in other files that it names "
                          "(bracket.stp, bolt.step, nut_prt.stp) and holds no B-Rep faces itself");
  // A part with geometry of its own that also names another file: read, with a warning.
  std::string bracket = ReadAll(test::DataFile("l_bracket.step"));
  const size_t end = bracket.rfind("ENDSEC;");
  ASSERT_NE(end, std::string::npos);
  bracket.insert(end, "#99990=EXTERNAL_SOURCE(IDENTIFIER('washer.stp'));\n");
  const fs::path q = TempDir() / "bracket-naming-a-washer.step";
  Write(q, bracket);
  const BRepModel m = ConvertStepFile(q.string(), ConversionOptions());
  int named = 0;
  for (const std::string& w : m.Stats.Warnings)
    named += w.find("names other STEP files as the sources of parts (washer.stp)") != std::string::npos;
  EXPECT_EQ(named, 1);
  EXPECT_GT(m.Faces.size(), 0u);
  const BRepModel plain = ConvertStepFile(test::DataFile("l_bracket.step"), ConversionOptions());
  for (const std::string& w : plain.Stats.Warnings)
    EXPECT_EQ(w.find("names other STEP files"), std::string::npos) << w;
}

// A drawing (a DRAUGHTING_MODEL of 2D views, as CAx-IF's drawing test files hold) and no face.
TEST(BadInput, DrawingOnly)
{
  const fs::path p = TempDir() / "drawing-only.step";
  Write(p, OnePartFile(R"(#9=DRAUGHTING_MODEL('sheet 1',(#13),#20);
#13=AXIS2_PLACEMENT_2D('',#14,#15);
#14=CARTESIAN_POINT('',(0.,0.));
#15=DIRECTION('',(1.,0.));)"));
  ExpectError(p.string(), "holds a drawing (a draughting model of 2D views) and no B-Rep faces");
}

// Constructive solid geometry only (a CSG_SOLID of a Boolean of blocks): OpenCASCADE reads no
// CSG, and the error says so.
TEST(BadInput, ConstructiveSolidOnly)
{
  const fs::path p = TempDir() / "csg-only.step";
  Write(p, OnePartFile(R"(#9=CSG_SHAPE_REPRESENTATION('',(#10),#20);
#10=CSG_SOLID('',#11);
#11=BOOLEAN_RESULT('',.DIFFERENCE.,#12,#13);
#12=BLOCK('',#14,10.,10.,10.);
#13=BLOCK('',#14,5.,5.,20.);
#14=AXIS2_PLACEMENT_3D('',#15,#16,#17);
#15=CARTESIAN_POINT('',(0.,0.,0.));
#16=DIRECTION('',(0.,0.,1.));
#17=DIRECTION('',(1.,0.,0.));)"));
  ExpectError(p.string(), "holds constructive solid geometry (");
}

TEST(BadInput, Directory)
{
  ExpectError(TempDir().string(), "is a directory");
}

TEST(BadInput, TwoGigabyteSparseFile)
{
  const fs::path p = TempDir() / "huge-sparse.step";
  {
    std::ofstream touch(p);
  }
  fs::resize_file(p, 2ull * 1024 * 1024 * 1024);
  ExpectError(p.string(), "binary data");
  fs::remove(p);
}

TEST(BadInput, AnyLetterCaseOfTheExtensionReads)
{
  for (const char* name : { "PLATE.STEP", "Plate.Stp", "plate.stp", "plate.STP" })
  {
    const fs::path p = TempDir() / name;
    fs::copy_file(test::DataFile("plate.step"), p, fs::copy_options::overwrite_existing);
    EXPECT_EQ(ConvertStepFile(p.string(), ConversionOptions()).Stats.Faces, 6) << name;
  }
}

TEST(StepSchemas, AP203AP214AP242)
{
  // The generator writes the plate as AP203, the tube as AP242 and the rest as AP214.
  StepReadResult info;
  (void)ReadStepFile(test::DataFile("plate.step"), &info);
  EXPECT_NE(info.Schema.find("CONFIG_CONTROL_DESIGN"), std::string::npos) << info.Schema;
  (void)ReadStepFile(test::DataFile("tube.step"), &info);
  EXPECT_NE(info.Schema.find("AP242"), std::string::npos) << info.Schema;
  (void)ReadStepFile(test::DataFile("hole_plate.step"), &info);
  EXPECT_NE(info.Schema.find("AUTOMOTIVE_DESIGN"), std::string::npos) << info.Schema;
}
} // namespace
