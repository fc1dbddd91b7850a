# Renders the cutter head: rotor cells (zone 0) clipped to show the blocked staircase, and the
# DEM wall triangles, side by side.
from paraview.simple import *
import sys, glob
# usage: xvfb-run -a pvbatch docs/render_cutter_head.py RESULTS_DIR OUT.png
# (RESULTS_DIR from `spillage run cases/cutter_head.toml`)
results, out = sys.argv[1], sys.argv[2]
fluid = XMLUnstructuredGridReader(FileName=[sorted(glob.glob(results + '/vtk/fluid_*.vtu'))[0]])
walls_files = sorted(glob.glob(results + '/vtk/walls_*'))
walls = XMLPolyDataReader(FileName=[walls_files[0]]) if walls_files[0].endswith('.vtp') else XMLUnstructuredGridReader(FileName=[walls_files[0]])
rotor = Threshold(Input=fluid)
rotor.Scalars = ['CELLS', 'zone']
rotor.LowerThreshold = 0; rotor.UpperThreshold = 0
# cells of one layer band: clip by a plane through the axis to show the staircase in section
clip = Clip(Input=rotor); clip.ClipType = 'Plane'; clip.ClipType.Normal = [0, 1, 0]; clip.ClipType.Origin = [0, 0, 0]
clip.Crinkleclip = 1
view = CreateView('RenderView'); view.ViewSize = [1600, 800]
try:
    view.UseColorPaletteForBackground = 0
except Exception: pass
view.Background = [1, 1, 1]
try:
    view.OrientationAxesVisibility = 0
except Exception: pass
layout = CreateLayout('head'); AssignViewToLayout(view=view, layout=layout)
d1 = Show(clip, view); d1.SetRepresentationType('Surface With Edges'); d1.DiffuseColor = [0.55, 0.7, 0.9]; d1.EdgeColor = [0.1, 0.1, 0.3]
tr = Transform(Input=walls); tr.Transform.Translate = [-1.1, 0, 0]
d2 = Show(tr, view); d2.SetRepresentationType('Surface With Edges'); d2.DiffuseColor = [0.85, 0.6, 0.4]; d2.EdgeColor = [0.3, 0.2, 0.1]
d1.ColorArrayName = [None, ""]; d2.ColorArrayName = [None, ""]
view.CameraPosition = [-0.55, 1.9, 0.65]; view.CameraFocalPoint = [-0.55, 0, -0.25]; view.CameraViewUp = [0, 0, 1]
view.CameraParallelProjection = 0
Render(view)
SaveScreenshot(out, view, ImageResolution=[1600, 800])
