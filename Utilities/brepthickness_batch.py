"""BRepThickness batch run: the wall thickness of a STEP part, written to files.

    pvpython Utilities/brepthickness_batch.py MODEL.step [--out DIR] [options]

Writes, under DIR (default ./brepthickness-out/<model>):
  <model>-thickness.vtp    display mesh with Thickness, Radius, SphereCenter, FootPoint,
                           ContactType, FailReason, Residual, Iterations, OppositeFaceId
  <model>-medial.vtp       medial points (sphere centres) with Radius, Thickness, SampleId
  <model>-summary.csv      thickness statistics, contact counts, times, conversion statistics
  <model>-histogram.csv    area-weighted thickness histogram
  <model>-residuals.csv    histogram of log10 |R| per contact type
  <model>.png              thickness map with a scalar bar (failed samples in magenta)
  <model>-medial.png       medial points coloured by thickness, in the part's silhouette
Prints a one-screen summary. Exits with status 1 and one message on bad input.
"""
import argparse
import csv
import math
import os
import re
import sys

# Colour map of the paper: white at zero, then blue, green, yellow, red at the maximum.
THICKNESS_RGB = [0.0, 1, 1, 1, 0.25, 0, 0, 1, 0.5, 0, 1, 0, 0.75, 1, 1, 0, 1.0, 1, 0, 0]
FAILED_RGB = [1.0, 0.0, 1.0]


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model", help="STEP file (.step/.stp)")
    ap.add_argument("--out", default=None, help="output folder (default ./brepthickness-out/<model>)")
    ap.add_argument("--plugin", default=os.environ.get("BRT_PLUGIN"),
                    help="BRepThickness.so (default: $BRT_PLUGIN, else PV_PLUGIN_PATH)")
    ap.add_argument("--tolerance", type=float, default=1e-4, help="Bezier conversion tolerance (mm)")
    ap.add_argument("--max-edge", type=float, default=0.0,
                    help="longest display-mesh edge, sets the sample density (mm; 0: diagonal/50)")
    ap.add_argument("--delaunay", action="store_true",
                    help="refine the display mesh with Delaunay flips (the reader's DelaunayRefinement): "
                         "well-shaped triangles, far fewer samples on cylinders and long faces")
    ap.add_argument("--time-limit", type=float, default=300.0,
                    help="seconds reading, healing and converting the STEP file may take (0: none; "
                         "OpenCASCADE runs in a separate process, a crash or a time-out there is an error)")
    ap.add_argument("--device", default="auto", help="auto, native, gpu, cpu or an OpenCL device name")
    ap.add_argument("--precision", choices=("float", "double"), default="float")
    ap.add_argument("--method", choices=("sphere", "sphere-and-ray", "ray"), default="sphere",
                    help="sphere: maximal-sphere thickness; sphere-and-ray: also the ray thickness "
                         "(RayThickness array, Summary rows RayThicknessMin/Max/Mean, RayMissed); "
                         "ray: the ray thickness alone (no spheres, no medial points)")
    ap.add_argument("--min-thickness", type=float, default=0.0, help="report the area thinner than this")
    ap.add_argument("--max-thickness", type=float, default=0.0, help="report the area thicker than this")
    ap.add_argument("--gap", action="store_true",
                    help="also the exterior gap (the air between walls; Gap array, Summary Gap rows)")
    ap.add_argument("--gap-only", action="store_true", help="the exterior gap alone, no thickness")
    ap.add_argument("--gap-scope", choices=("own-solid", "all-solids"), default="own-solid",
                    help="walls that bound the gap: the sample's solid, or every solid of the file")
    ap.add_argument("--min-gap", type=float, default=0.0, help="report the area with a narrower gap")
    ap.add_argument("--max-gap", type=float, default=0.0, help="gaps wider than this count as infinite")
    ap.add_argument("--edge-zone-angle", type=float, default=60.0,
                    help="corners of at least this material angle (degrees) make edge zones")
    ap.add_argument("--count-edge-zones", action="store_true",
                    help="edge zones count against --min-thickness/--max-thickness (default: not)")
    ap.add_argument("--s1-spacing", type=float, default=0.0, help="coarse sample spacing on the faces (mm; a third of it along the edges; 0: diagonal/150, edges diagonal/900)")
    ap.add_argument("--clearance", type=float, default=-1.0,
                    help="boundary points less deep than this in a sphere do not limit it "
                         "(mm; negative: twice --tolerance; 0: the paper's eq. 1)")
    ap.add_argument("--bins", type=int, default=20, help="bins of the thickness histogram")
    ap.add_argument("--midsurface", action="store_true",
                    help="also the midsurface of the thin walls (B-Rep Midsurface): .vtp, a CalculiX "
                         "shell deck (.inp) and a picture over the see-through part")
    ap.add_argument("--skeleton", action="store_true",
                    help="also the skeleton of the rod-like regions (B-Rep Skeleton): .vtp")
    ap.add_argument("--linear-shells", action="store_true",
                    help="S3 elements in the shell deck instead of S6")
    ap.add_argument("--size", type=int, nargs=2, default=(1200, 900), metavar=("W", "H"))
    return ap.parse_args(argv)


def load_plugin(path):
    import paraview.simple as simple
    if path:
        if not os.path.isfile(path):
            sys.exit("error: plugin '%s' does not exist (build the project first)" % path)
        simple.LoadPlugin(path)  # adds the plugin's proxies to paraview.simple
    reader = getattr(simple, "STEPReader", None)
    thickness = getattr(simple, "BRepThickness", None)
    if reader is None or thickness is None:
        sys.exit("error: the BRepThickness plugin is not loaded (give --plugin or set PV_PLUGIN_PATH)")
    return reader, thickness


def collect_errors(proxy, errors):
    """Collects the error messages of a proxy's VTK object (the reader names the file)."""
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_STRING

    @calldata_type(VTK_STRING)
    def on_error(obj, event, message):
        # VTK's format: "ERROR: In <file>, line <n>\n<class> (<address>): <message>\n"
        lines = message.strip().splitlines()
        text = "\n".join(lines[1:] if len(lines) > 1 and lines[0].startswith("ERROR: In ") else lines)
        errors.append(re.sub(r"^\w+ \(0x[0-9a-fA-F]+\): ", "", text))

    proxy.GetClientSideObject().AddObserver("ErrorEvent", on_error)


def updated(proxy, errors):
    """Updates a filter proxy; its first error ends the batch with that message."""
    collect_errors(proxy, errors)
    proxy.UpdatePipeline()
    if errors:
        sys.exit("error: " + errors[0])
    return proxy


def table_rows(table):
    cols = [table.GetColumn(c) for c in range(table.GetNumberOfColumns())]
    names = [c.GetName() for c in cols]
    rows = [[c.GetValue(r) for c in cols] for r in range(table.GetNumberOfRows())]
    return names, rows


def fmt(v):
    return "" if isinstance(v, float) and math.isnan(v) else v


def render(source, port, view, name_png, size, lut, tmax, title, points=False, context=None,
           array="Thickness"):
    import paraview.simple as simple
    for rep in view.Representations:
        if hasattr(rep, "Visibility"):
            rep.Visibility = 0
    if context is not None:
        ctx = simple.Show(context, view)
        simple.ColorBy(ctx, None)
        ctx.Opacity = 0.15
        ctx.DiffuseColor = [0.6, 0.6, 0.6]
    display = simple.Show(simple.OutputPort(source, port), view)
    simple.ColorBy(display, ("POINTS", array))
    display.LookupTable = lut
    lut.RescaleTransferFunction(0.0, tmax)  # white at zero, red at the maximum
    if points:
        display.SetRepresentationType("Points")
        display.PointSize = 3
    display.SetScalarBarVisibility(view, True)
    bar = simple.GetScalarBar(lut, view)
    bar.Title = title
    bar.ComponentTitle = ""
    bar.RangeLabelFormat = "%-#6.3g"
    bar.WindowLocation = "Any Location"
    bar.Position = [0.88, 0.1]
    bar.ScalarBarLength = 0.8
    view.CameraPosition = [1, -1.3, 0.9]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 0, 1]
    simple.ResetCamera(view)
    simple.Render(view)
    simple.SaveScreenshot(name_png, view, ImageResolution=list(size))


def main(argv=None):
    args = parse_args(argv)
    import paraview.simple as simple
    from paraview import servermanager as sm
    STEPReader, BRepThickness = load_plugin(args.plugin)

    name = os.path.splitext(os.path.basename(args.model))[0]
    out = args.out or os.path.join("brepthickness-out", name)
    errors = []
    reader = STEPReader(FileName=os.path.abspath(args.model), Tolerance=args.tolerance,
                        MaxEdgeLength=args.max_edge, DelaunayRefinement=int(args.delaunay),
                        TimeLimit=args.time_limit)
    collect_errors(reader, errors)
    reader.UpdatePipeline()
    if errors:
        sys.exit("error: " + errors[0])
    thick = BRepThickness(Input=reader, Device=args.device,
                          Precision="Double" if args.precision == "double" else "Float",
                          MinimumThickness=args.min_thickness, MaximumThickness=args.max_thickness,
                          S1Spacing=args.s1_spacing, Clearance=args.clearance, HistogramBins=args.bins,
                          Method={"sphere": "Sphere", "sphere-and-ray": "Sphere and ray", "ray": "Ray"}[args.method],
                          EdgeZoneAngle=args.edge_zone_angle, CountEdgeZones=int(args.count_edge_zones),
                          Measure="Gap" if args.gap_only else "Thickness and gap" if args.gap else "Thickness",
                          GapScope="All solids" if args.gap_scope == "all-solids" else "Own solid",
                          MinimumGap=args.min_gap, MaximumGap=args.max_gap)
    collect_errors(thick, errors)
    thick.UpdatePipeline()
    if errors:
        sys.exit("error: " + errors[0])

    mesh = sm.Fetch(thick, idx=0)
    summary = sm.Fetch(thick, idx=3)
    residuals = sm.Fetch(thick, idx=2)
    if mesh.GetNumberOfPoints() == 0 or summary.GetNumberOfRows() == 0:
        sys.exit("error: STEP file '%s': the thickness filter produced no result" % args.model)
    fd = mesh.GetFieldData()
    unit = fd.GetAbstractArray("LengthUnit").GetValue(0)
    device = summary.GetFieldData().GetAbstractArray("Device").GetValue(0)

    os.makedirs(out, exist_ok=True)
    files = {}
    files["thickness"] = os.path.join(out, name + "-thickness.vtp")
    simple.SaveData(files["thickness"], proxy=simple.OutputPort(thick, 0))
    ray_only = args.method == "ray" and not args.gap_only
    # What the limits, tables and the picture measure.
    measure = "Gap" if args.gap_only else "RayThickness" if ray_only else "Thickness"
    if not ray_only and not args.gap_only:  # no thickness spheres: no medial points, no residuals
        files["medial"] = os.path.join(out, name + "-medial.vtp")
        simple.SaveData(files["medial"], proxy=simple.OutputPort(thick, 1))

    _, rows = table_rows(summary)
    stats = {r[0]: r[1] for r in rows}
    units = {r[0]: r[2] for r in rows}
    conversion = ["NumberOfSolids", "NumberOfFaces", "NumberOfPatches", "NumberOfTrimSegments",
                  "NumberOfEdges", "MaxPatchDeviation", "ReadSeconds", "HealSeconds", "ConvertSeconds",
                  "MeshSeconds"]
    files["summary"] = os.path.join(out, name + "-summary.csv")
    with open(files["summary"], "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["quantity", "value", "unit"])
        w.writerow(["SourceFile", os.path.abspath(args.model), ""])
        w.writerow(["Device", device, ""])
        for k, v in stats.items():
            w.writerow([k, fmt(v), units[k]])
        for k in conversion:
            w.writerow([k, fd.GetArray(k).GetValue(0), "s" if k.endswith("Seconds") else ""])
    files["histogram"] = os.path.join(out, name + "-histogram.csv")
    histogram = sm.Fetch(thick, idx=4)
    width = histogram.GetFieldData().GetArray("BinWidth").GetValue(0)
    with open(files["histogram"], "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["thickness_from_" + unit, "thickness_to_" + unit, "area_share"])
        for r in table_rows(histogram)[1]:
            w.writerow([fmt(r[0] - width / 2), fmt(r[0] + width / 2), fmt(r[1])])
    # Per solid and per face, with the unit in every header that has one.
    table_units = {"Area": unit + "^2", measure + "Min": unit, measure + "Max": unit,
                   measure + "Mean": unit}
    for key, port in (("per_solid", 5), ("per_face", 6)):
        files[key] = os.path.join(out, name + "-" + key.replace("_", "-") + ".csv")
        names, trows = table_rows(sm.Fetch(thick, idx=port))
        with open(files[key], "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["%s_%s" % (n, table_units[n]) if n in table_units else n for n in names])
            w.writerows([[fmt(v) if isinstance(v, float) else v for v in r] for r in trows])
    files["residuals"] = os.path.join(out, name + "-residuals.csv")
    with open(files["residuals"], "w", newline="") as f:  # empty with --method ray
        names, rows = table_rows(residuals)
        w = csv.writer(f)
        w.writerow(names)
        w.writerows(rows)

    # Pictures: the thickness map, then the medial points.
    view = simple.CreateView("RenderView")
    view.ViewSize = list(args.size)
    view.OrientationAxesVisibility = 1
    view.Background = [1, 1, 1]
    try:  # ParaView >= 5.10: the palette decides the background unless told otherwise
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.OrientationAxesLabelColor = [0, 0, 0]
    lut = simple.GetColorTransferFunction(measure)
    lut.ColorSpace = "RGB"
    tmax = stats[measure + "Max"] if stats[measure + "Max"] > 0 else 1.0
    lut.RGBPoints = [x * (tmax if i % 4 == 0 else 1) for i, x in enumerate(THICKNESS_RGB)]
    lut.NanColor = FAILED_RGB
    lut.AutomaticRescaleRangeMode = "Never"
    title = "%s (%s)" % ({"Gap": "Gap", "RayThickness": "Ray thickness"}.get(measure, "Thickness"), unit)
    files["png"] = os.path.join(out, name + ".png")
    render(thick, 0, view, files["png"], args.size, lut, tmax, title, array=measure)
    bar = simple.GetScalarBar(lut, view)
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    simple.SaveScreenshot(files["png"], view, ImageResolution=list(args.size))
    if "medial" in files:
        files["medial_png"] = os.path.join(out, name + "-medial.png")
        render(thick, 1, view, files["medial_png"], args.size, lut, tmax, title, points=True,
               context=simple.OutputPort(thick, 0))
    skel_fields = None
    skel = None
    if args.skeleton and measure == "Thickness":
        skel = updated(simple.BRepSkeleton(Input=thick), errors)
        files["skeleton"] = os.path.join(out, name + "-skeleton.vtp")
        simple.SaveData(files["skeleton"], proxy=skel)
        skel_data = sm.Fetch(skel)
        sfd = skel_data.GetFieldData()
        skel_fields = {k: sfd.GetArray(k).GetValue(0) if sfd.GetArray(k) else 0 for k in
                       ("Branches", "JunctionNodes", "EndNodes", "RodSamples", "RemovedSpurs",
                        "NoiseClusters")}

    mid_rows = None
    if args.midsurface and measure == "Thickness":
        mid = updated(simple.BRepMidsurface(Input=thick), errors)
        mid_rows = dict(table_rows(sm.Fetch(mid, idx=2))[1])
        files["midsurface"] = os.path.join(out, name + "-midsurface.vtp")
        simple.SaveData(files["midsurface"], proxy=simple.OutputPort(mid, 0))
        if mid_rows["Sheets"] > 0:
            files["deck"] = os.path.join(out, name + "-midsurface.inp")
            simple.SaveData(files["deck"], proxy=simple.OutputPort(mid, 0),
                            Quadratic=0 if args.linear_shells else 1)
        files["midsurface_png"] = os.path.join(out, name + "-midsurface.png")
        render(mid, 0, view, files["midsurface_png"], args.size, lut, tmax, title,
               context=simple.OutputPort(thick, 0))
        if skel is not None and skel_data.GetNumberOfPoints() > 0:  # the rods' skeleton, black
            lines = simple.Show(skel, view)
            simple.ColorBy(lines, None)
            lines.AmbientColor = lines.DiffuseColor = [0.0, 0.0, 0.0]
            lines.LineWidth = 4.0
            simple.Render(view)
            simple.SaveScreenshot(files["midsurface_png"], view, ImageResolution=list(args.size))

    n = stats["Samples"]
    share = lambda k: 100.0 * stats[k] / n if n else 0.0
    print("BRepThickness: %s  (%s)" % (args.model, device))
    print("  %d faces -> %d bicubic patches (max deviation %.1e %s); %d samples, %d s1 points"
          % (fd.GetArray("NumberOfFaces").GetValue(0), fd.GetArray("NumberOfPatches").GetValue(0),
             fd.GetArray("MaxPatchDeviation").GetValue(0), unit, n, stats["S1Points"]))
    if ray_only:
        print("  rays: %d (%.3f%%) met nothing" % (stats["RayMissed"], share("RayMissed")))
    elif args.gap_only:
        pass
    else:
        print("  contacts: %.1f%% surface/surface, %.1f%% surface/edge, %.1f%% surface/vertex, %.2f%% osculating, "
              "%.2f%% failed" % (share("SurfaceSurface"), share("SurfaceEdge"), share("SurfaceVertex"),
                                 share("Osculating") if "Osculating" in stats else 0.0, share("Failed")))
    failed = [(k[len("Failed"):], int(v)) for k, v in stats.items() if k.startswith("Failed") and k != "Failed" and v]
    if failed:
        print("  failed: " + ", ".join("%s %d" % kv for kv in failed))
    if not args.gap_only:
        print("  %s: min %.4g, max %.4g, area-weighted mean %.4g %s"
              % ("ray thickness" if ray_only else "thickness", stats[measure + "Min"], stats[measure + "Max"],
                 stats[measure + "Mean"], unit))
        print("  edge zones (corners of %g deg or more): %.2f%% of the area; the limits %s"
              % (args.edge_zone_angle, 100 * stats["AreaShareEdgeZone"],
                 "count them" if args.count_edge_zones else "leave them out"))
        if args.min_thickness > 0:
            print("  area thinner than %g %s: %.2f%% without edge zones, %.2f%% with them"
                  % (args.min_thickness, unit, 100 * stats["AreaShareBelowMinimumWithoutEdgeZones"],
                     100 * stats["AreaShareBelowMinimumWithEdgeZones"]))
        if args.max_thickness > 0:
            print("  area thicker than %g %s: %.2f%% without edge zones, %.2f%% with them"
                  % (args.max_thickness, unit, 100 * stats["AreaShareAboveMaximumWithoutEdgeZones"],
                     100 * stats["AreaShareAboveMaximumWithEdgeZones"]))
    if args.gap or args.gap_only:
        print("  gap (%s): min %.4g, max %.4g, area-weighted mean %.4g %s; infinite on %.2f%% of the area; "
              "0 on another solid (touching or overlapping) on %.2f%%; %d samples failed%s"
              % (args.gap_scope, stats["GapMin"], stats["GapMax"], stats["GapMean"], unit,
                 100 * stats["AreaShareInfiniteGap"], 100 * stats["AreaShareOnOtherSolid"],
                 stats["GapFailed"],
                 "; below %g %s: %.2f%%" % (args.min_gap, unit, 100 * stats["AreaShareBelowMinimumGap"])
                 if args.min_gap > 0 else ""))
    if mid_rows is not None:
        print("  midsurface: %d sheets (%.4g %s^2), %d junction lines (%d non-manifold edges), %d open "
              "junction edges; %d sphere centres, %d vertices carried to the outline; %d samples pruned "
              "in %d branches; %d faces (%.4g %s^2) not thin"
              % (mid_rows["Sheets"], mid_rows["SheetArea"], unit, mid_rows["Junctions"],
                 mid_rows["NonManifoldEdges"], mid_rows["OpenJunctionEdges"], mid_rows["SheetSamples"],
                 mid_rows["ExtendedVertices"], mid_rows["PrunedSamples"], mid_rows["PrunedBranches"],
                 mid_rows["NotThinFaces"], mid_rows["NotThinArea"], unit))
    if skel_fields:
        print("  skeleton: %d branches, %d junctions, %d free ends from %d rod samples; %d spurs "
              "removed, %d noise clusters"
              % (skel_fields["Branches"], skel_fields["JunctionNodes"], skel_fields["EndNodes"],
                 skel_fields["RodSamples"], skel_fields["RemovedSpurs"], skel_fields["NoiseClusters"]))
    elif args.skeleton:
        print("  skeleton: needs the thickness (not with --gap-only or --method ray)")
    if mid_rows is None and args.midsurface:
        print("  midsurface: needs the thickness (not with --gap-only or --method ray)")
    print("  solids: " + ", ".join(
        "%d: %.4g .. %.4g %s" % (r[0], r[4], r[5], unit) for r in table_rows(sm.Fetch(thick, idx=5))[1]))
    print("  times: read %.2f s, convert %.2f s, mesh %.2f s, prepare %.2f s, solve %.2f s"
          % (fd.GetArray("ReadSeconds").GetValue(0) + fd.GetArray("HealSeconds").GetValue(0),
             fd.GetArray("ConvertSeconds").GetValue(0), fd.GetArray("MeshSeconds").GetValue(0),
             stats["PrepareSeconds"], stats["SolveSeconds"]))
    for key in ("thickness", "medial", "summary", "histogram", "per_solid", "per_face", "residuals", "png",
                "medial_png", "midsurface", "deck", "midsurface_png", "skeleton"):
        if key in files:
            print("  wrote %s" % files[key])
    # Release the view (and its OpenGL context) before the interpreter's teardown closes X.
    simple.Delete(view)
    del view
    return 0


if __name__ == "__main__":
    sys.exit(main())
