"""The plugin loads with LoadPlugin(path, ns=globals()) and through PV_PLUGIN_PATH.

Usage: pvpython test_plugin_load.py PLUGIN_FILE MODEL.step
With PLUGIN_FILE '-' the plugin must already be loaded through PV_PLUGIN_PATH.
"""
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm

plugin, model = sys.argv[1], sys.argv[2]
if plugin != "-":
    assert "STEPReader" not in globals(), "STEPReader exists before LoadPlugin"
    LoadPlugin(plugin, ns=globals())
else:
    assert os.environ.get("PV_PLUGIN_PATH"), "PV_PLUGIN_PATH is not set"
    # Plugins found through PV_PLUGIN_PATH are loaded at start-up; paraview.simple then has the
    # proxies of every loaded plugin.
    import paraview.simple as simple
    assert hasattr(simple, "STEPReader"), "STEPReader not loaded through PV_PLUGIN_PATH"
    STEPReader = simple.STEPReader

reader = STEPReader(FileName=model)
reader.UpdatePipeline()
data = sm.Fetch(reader)
assert data.GetNumberOfPoints() > 0, "reader produced no points"
assert data.GetPointData().GetArray("FaceId") is not None
print("loaded through %s: %d points, %d triangles" % (
    "LoadPlugin" if plugin != "-" else "PV_PLUGIN_PATH", data.GetNumberOfPoints(),
    data.GetNumberOfCells()))
