// Writes the analytic test solids of Data/ as STEP files. Every one has a wall thickness known
// in closed form; Data/README.md lists them. Usage: brt_make_analytic_models OUTPUT_DIR
#include "AnalyticShapes.h"

#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>

#include <cmath>
#include <cstring>
#include <iostream>
#include <string>

namespace
{
bool Write(const TopoDS_Shape& shape, const std::string& path, const char* schema)
{
  Interface_Static::SetCVal("write.step.schema", schema);
  Interface_Static::SetCVal("write.step.unit", "MM");
  STEPControl_Writer writer;
  if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone ||
    writer.Write(path.c_str()) != IFSelect_RetDone)
  {
    std::cerr << "cannot write " << path << "\n";
    return false;
  }
  std::cout << "wrote " << path << " (" << schema << ")\n";
  return true;
}

} // namespace

int main(int argc, char** argv)
{
  const bool help = argc == 2 && (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h"));
  if (argc != 2 || help)
  {
    (help ? std::cout : std::cerr)
      << "usage: " << argv[0] << " OUTPUT_DIR\n"
      << "Writes the analytic models of Data/ (plate, tube, spherical and toroidal shells, hole\n"
         "plate, L-bracket, T profile, cubic ridge; thicknesses in Data/README.md) as STEP files into OUTPUT_DIR.\n";
    return help ? 0 : 2;
  }
  const std::string dir = argv[1];
  STEPControl_Controller::Init(); // before the first SetCVal, which would else be overwritten
  bool ok = true;
  using namespace brt::analytic;
  // Dimensions and thicknesses: Data/README.md.
  ok &= Write(Plate(100.0, 60.0, 5.0), dir + "/plate.step", "AP203");
  ok &= Write(Tube(20.0, 15.0, 80.0), dir + "/tube.step", "AP242DIS");
  ok &= Write(SphericalShell(25.0, 20.0), dir + "/spherical_shell.step", "AP214IS");
  ok &= Write(ToroidalShell(40.0, 10.0, 6.0), dir + "/toroidal_shell.step", "AP214IS");
  ok &= Write(HolePlate(80.0, 6.0, 10.0), dir + "/hole_plate.step", "AP214IS");
  ok &= Write(LBracket(60.0, 8.0, 40.0, 5.0), dir + "/l_bracket.step", "AP214IS");
  ok &= Write(TProfile(80.0, 6.0, 40.0, 4.0, 30.0), dir + "/t_profile.step", "AP214IS");
  ok &= Write(CubicRidge(10.0, 0.5, 0.3, 2.0, 4.0, 0.6, 1.0), dir + "/cubic_ridge.step", "AP214IS");
  return ok ? 0 : 1;
}
