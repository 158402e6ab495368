// Writes the analytic test solids of Data/ as STEP files. Every one has a wall thickness known
// in closed form; Data/README.md lists them. Usage: brt_make_analytic_models OUTPUT_DIR
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Ax2.hxx>
#include <gp_Pnt.hxx>

#include <cmath>
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

/// L-bracket: two legs of length 60 and thickness 8, width 40, with a fillet of radius 5 on the
/// inner (concave) corner edge.
TopoDS_Shape LBracket()
{
  const double L = 60.0, T = 8.0, W = 40.0, R = 5.0;
  BRepBuilderAPI_MakePolygon poly;
  poly.Add(gp_Pnt(0, 0, 0));
  poly.Add(gp_Pnt(L, 0, 0));
  poly.Add(gp_Pnt(L, T, 0));
  poly.Add(gp_Pnt(T, T, 0));
  poly.Add(gp_Pnt(T, L, 0));
  poly.Add(gp_Pnt(0, L, 0));
  poly.Close();
  const TopoDS_Face profile = BRepBuilderAPI_MakeFace(poly.Wire());
  const TopoDS_Shape prism = BRepPrimAPI_MakePrism(profile, gp_Vec(0, 0, W));
  BRepFilletAPI_MakeFillet fillet(prism);
  for (TopExp_Explorer ex(prism, TopAbs_EDGE); ex.More(); ex.Next())
  {
    const TopoDS_Edge e = TopoDS::Edge(ex.Current());
    double f, l;
    Handle(Geom_Curve) c = BRep_Tool::Curve(e, f, l);
    const gp_Pnt a = c->Value(f), b = c->Value(l);
    // The inner corner edge runs along z through (T, T).
    if (std::fabs(a.X() - T) < 1e-9 && std::fabs(a.Y() - T) < 1e-9 &&
      std::fabs(b.X() - T) < 1e-9 && std::fabs(b.Y() - T) < 1e-9)
      fillet.Add(R, e);
  }
  return fillet.Shape();
}
} // namespace

int main(int argc, char** argv)
{
  if (argc != 2)
  {
    std::cerr << "usage: " << argv[0] << " OUTPUT_DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  STEPControl_Controller::Init(); // before the first SetCVal, which would else be overwritten
  bool ok = true;
  // Plate 100 x 60 x 5: thickness 5.
  ok &= Write(BRepPrimAPI_MakeBox(100.0, 60.0, 5.0).Shape(), dir + "/plate.step", "AP203");
  // Coaxial tube, radii 20 and 15, length 80: wall 5.
  {
    const gp_Ax2 axis(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1));
    TopoDS_Shape outer = BRepPrimAPI_MakeCylinder(axis, 20.0, 80.0).Shape();
    TopoDS_Shape inner = BRepPrimAPI_MakeCylinder(axis, 15.0, 80.0).Shape();
    ok &= Write(BRepAlgoAPI_Cut(outer, inner).Shape(), dir + "/tube.step", "AP242DIS");
  }
  // Spherical shell, radii 25 and 20: wall 5.
  {
    TopoDS_Shape outer = BRepPrimAPI_MakeSphere(25.0).Shape();
    TopoDS_Shape inner = BRepPrimAPI_MakeSphere(20.0).Shape();
    ok &= Write(BRepAlgoAPI_Cut(outer, inner).Shape(), dir + "/spherical_shell.step", "AP214IS");
  }
  // Toroidal shell, major radius 40, tube radii 10 and 6: wall 4.
  {
    TopoDS_Shape outer = BRepPrimAPI_MakeTorus(40.0, 10.0).Shape();
    TopoDS_Shape inner = BRepPrimAPI_MakeTorus(40.0, 6.0).Shape();
    ok &= Write(BRepAlgoAPI_Cut(outer, inner).Shape(), dir + "/toroidal_shell.step", "AP214IS");
  }
  // Plate 80 x 80 x 6 with a through hole of radius 10 at its centre: thickness 6.
  {
    TopoDS_Shape plate = BRepPrimAPI_MakeBox(80.0, 80.0, 6.0).Shape();
    TopoDS_Shape hole =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(40, 40, -1), gp_Dir(0, 0, 1)), 10.0, 8.0).Shape();
    ok &= Write(BRepAlgoAPI_Cut(plate, hole).Shape(), dir + "/hole_plate.step", "AP214IS");
  }
  // L-bracket, legs 60 x 8, width 40, inner fillet radius 5: thickness 8 away from the corner.
  ok &= Write(LBracket(), dir + "/l_bracket.step", "AP214IS");
  return ok ? 0 : 1;
}
