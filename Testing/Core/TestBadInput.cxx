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
