# Renders the worn walls of a run with [wear]: the last walls frame coloured by wear_depth (point
# data), seen obliquely so the scar's depth shows as relief (displaced 20× along its normals).
from paraview.simple import *
import sys, glob
# usage: xvfb-run -a pvbatch docs/render_wear.py RESULTS_DIR OUT.png [EXAGGERATION]
results, out = sys.argv[1], sys.argv[2]
exaggeration = float(sys.argv[3]) if len(sys.argv) > 3 else 1.0
walls = XMLPolyDataReader(FileName=[sorted(glob.glob(results + '/vtk/walls_*.vtp'))[-1]])
shape = walls
if exaggeration != 1.0:
    # the worn shape is already in the points; exaggerate the recession along the normals
    normals = GenerateSurfaceNormals(Input=walls); normals.Splitting = 0
    calc = Calculator(Input=normals); calc.ResultArrayName = 'shift'
    calc.Function = '-%g*wear_depth*Normals' % (exaggeration - 1.0)
    shape = WarpByVector(Input=calc); shape.Vectors = ['POINTS', 'shift']
view = CreateView('RenderView'); view.ViewSize = [1400, 800]
try:
    view.UseColorPaletteForBackground = 0
except Exception: pass
view.Background = [1, 1, 1]
layout = CreateLayout('wear'); AssignViewToLayout(view=view, layout=layout)
d = Show(shape, view); d.SetRepresentationType('Surface With Edges'); d.EdgeColor = [0.4, 0.4, 0.4]
ColorBy(d, ('POINTS', 'wear_depth'))
lut = GetColorTransferFunction('wear_depth'); lut.ApplyPreset('Inferno (matplotlib)', True)
bar = GetScalarBar(lut, view); bar.Title = 'wear depth [m]'; bar.ComponentTitle = ''; bar.Visibility = 1
bar.TitleColor = [0, 0, 0]; bar.LabelColor = [0, 0, 0]
view.ResetCamera()
cam = view.GetActiveCamera(); cam.Elevation(35); cam.Azimuth(-25)
view.ResetCamera()
Render(view)
SaveScreenshot(out, view, ImageResolution=[1400, 800])
