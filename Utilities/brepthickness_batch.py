"""BRepThickness batch run: read a STEP part and write its results.

    pvpython Utilities/brepthickness_batch.py MODEL.step [--out DIR] [--plugin PATH]
             [--tolerance T] [--max-edge L] [--size W H]

Writes, under DIR (default ./brepthickness-out/<model>):
  <model>.vtp             the reader's output (display mesh, FaceId/SolidId/FaceUV/Normals,
                          the converted B-Rep in field data)
  <model>-summary.csv     conversion statistics
  <model>.png             rendering coloured by FaceId, with a scalar bar
Until the thickness filter exists (issue 4) the map is coloured by FaceId.
Exits with status 1 and one message on bad input.
"""
import argparse
import csv
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model")
    ap.add_argument("--out", default=None)
    ap.add_argument("--plugin", default=os.environ.get("BRT_PLUGIN"),
                    help="BRepThickness.so (default: $BRT_PLUGIN, else PV_PLUGIN_PATH)")
    ap.add_argument("--tolerance", type=float, default=1e-4)
    ap.add_argument("--max-edge", type=float, default=0.0)
    ap.add_argument("--size", type=int, nargs=2, default=(1200, 900))
    args = ap.parse_args()

    from paraview.simple import (LoadPlugin, GetActiveViewOrCreate, Show, ColorBy, GetColorTransferFunction,
                                 ResetCamera, SaveScreenshot, SaveData, Render)
    from paraview import servermanager as sm
    import paraview.simple as simple
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_STRING

    ns = {}
    if args.plugin:
        if not os.path.isfile(args.plugin):
            sys.exit("error: plugin '%s' does not exist (build the project first)" % args.plugin)
        LoadPlugin(args.plugin, ns=ns)
    STEPReader = ns.get("STEPReader", getattr(simple, "STEPReader", None))
    if STEPReader is None:
        sys.exit("error: the BRepThickness plugin is not loaded (give --plugin or set PV_PLUGIN_PATH)")

    name = os.path.splitext(os.path.basename(args.model))[0]
    out = args.out or os.path.join("brepthickness-out", name)
    reader = STEPReader(FileName=os.path.abspath(args.model), Tolerance=args.tolerance,
                               MaxEdgeLength=args.max_edge)
    errors = []

    @calldata_type(VTK_STRING)
    def on_error(obj, event, message):
        errors.append(message.strip().splitlines()[-1])

    reader.GetClientSideObject().AddObserver("ErrorEvent", on_error)
    reader.UpdatePipeline()
    if errors:
        sys.exit("error: " + errors[0].split(": ", 1)[-1])
    data = sm.Fetch(reader)
    fd = data.GetFieldData()

    os.makedirs(out, exist_ok=True)
    vtp = os.path.join(out, name + ".vtp")
    SaveData(vtp, proxy=reader)

    keys = ["NumberOfSolids", "NumberOfFaces", "NumberOfPatches", "NumberOfLoops", "NumberOfTrimSegments",
            "NumberOfEdges", "NumberOfEdgeSegments", "Tolerance", "MaxPatchDeviation", "MaxEdgeDeviation",
            "MaxLoopGapUV", "MaxLoopGap3D", "OpenLoops", "ReadSeconds", "HealSeconds", "ConvertSeconds",
            "MeshSeconds"]
    summary = os.path.join(out, name + "-summary.csv")
    with open(summary, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["quantity", "value"])
        w.writerow(["SourceFile", os.path.abspath(args.model)])
        w.writerow(["LengthUnit", fd.GetAbstractArray("LengthUnit").GetValue(0)])
        w.writerow(["MeshPoints", data.GetNumberOfPoints()])
        for k in keys:
            w.writerow([k, fd.GetArray(k).GetValue(0)])
        warnings = fd.GetAbstractArray("ConversionWarnings")
        w.writerow(["Warnings", warnings.GetNumberOfValues()])

    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = list(args.size)
    view.OrientationAxesVisibility = 1
    display = Show(reader, view)
    ColorBy(display, ("POINTS", "FaceId"))
    lut = GetColorTransferFunction("FaceId")
    lut.ApplyPreset("Rainbow Uniform", True)
    display.SetScalarBarVisibility(view, True)
    bar = simple.GetScalarBar(lut, view)
    bar.Title = "FaceId"
    bar.ComponentTitle = ""
    view.CameraPosition = [1, -1.3, 0.9]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 0, 1]
    ResetCamera(view)
    Render(view)
    png = os.path.join(out, name + ".png")
    SaveScreenshot(png, view, ImageResolution=list(args.size))

    s = {k: fd.GetArray(k).GetValue(0) for k in keys}
    print("BRepThickness: %s" % args.model)
    print("  %d solids, %d faces -> %d bicubic patches (max deviation %.2e mm, tolerance %.0e)"
          % (s["NumberOfSolids"], s["NumberOfFaces"], s["NumberOfPatches"], s["MaxPatchDeviation"], s["Tolerance"]))
    print("  %d trimming segments in %d loops (%d open), %d edges in %d segments"
          % (s["NumberOfTrimSegments"], s["NumberOfLoops"], s["OpenLoops"], s["NumberOfEdges"],
             s["NumberOfEdgeSegments"]))
    print("  display mesh: %d points, %d triangles" % (data.GetNumberOfPoints(), data.GetNumberOfCells()))
    print("  read %.2f s, heal %.2f s, convert %.2f s, mesh %.2f s"
          % (s["ReadSeconds"], s["HealSeconds"], s["ConvertSeconds"], s["MeshSeconds"]))
    for path in (vtp, summary, png):
        print("  wrote %s" % path)


if __name__ == "__main__":
    main()
