# Renders the worn walls of a run with [wear]: the last walls frame coloured by wear_depth (per
# vertex), optionally one wall only, seen along an axis or obliquely.
# usage: xvfb-run -a pvbatch docs/render_wear.py RESULTS_DIR OUT.png [--wall N] [--view +x|-x|+y|-y|+z|-z]
#   --wall N   only wall N (its index in [[walls]], the `wall` cell field)
#   --view D   look from direction D (e.g. +y: from above a floor at the bottom of y)
from paraview.simple import *
import sys, glob
args = sys.argv[1:]
results, out = args[0], args[1]
options = dict(zip(args[2::2], args[3::2]))
walls = XMLPolyDataReader(FileName=[sorted(glob.glob(results + '/vtk/walls_*.vtp'))[-1]])
shape = walls
if '--wall' in options:
    n = float(options['--wall'])
    shape = Threshold(Input=walls); shape.Scalars = ['CELLS', 'wall']
    shape.LowerThreshold = n; shape.UpperThreshold = n
view = CreateView('RenderView'); view.ViewSize = [1600, 700]
try:
    view.UseColorPaletteForBackground = 0
except Exception: pass
view.Background = [1, 1, 1]
try:
    view.OrientationAxesVisibility = 1
except Exception: pass
layout = CreateLayout('wear'); AssignViewToLayout(view=view, layout=layout)
d = Show(shape, view); d.SetRepresentationType('Surface With Edges'); d.EdgeColor = [0.5, 0.5, 0.5]
ColorBy(d, ('POINTS', 'wear_depth'))
lut = GetColorTransferFunction('wear_depth'); lut.ApplyPreset('Inferno (matplotlib)', True)
d.RescaleTransferFunctionToDataRange(True, False)
bar = GetScalarBar(lut, view); bar.Title = 'wear depth [m]'; bar.ComponentTitle = ''; bar.Visibility = 1
bar.TitleColor = [0, 0, 0]; bar.LabelColor = [0, 0, 0]
view.ResetCamera()
if '--view' in options:
    direction = options['--view']
    axis = {'x': 0, 'y': 1, 'z': 2}[direction[1]]
    sign = 1.0 if direction[0] == '+' else -1.0
    cam = view.GetActiveCamera()
    focal = list(cam.GetFocalPoint())
    distance = cam.GetDistance()
    position = list(focal); position[axis] += sign * distance
    # keep the other axes pointing right and up on the screen (x to the right where it can)
    up = {0: [0.0, 0.0, 1.0], 1: [0.0, 0.0, -sign], 2: [0.0, sign, 0.0]}[axis]
    view.CameraPosition = position; view.CameraFocalPoint = focal; view.CameraViewUp = up
    view.ResetCamera()
    view.GetActiveCamera().Zoom(1.6)
else:
    cam = view.GetActiveCamera(); cam.Elevation(35); cam.Azimuth(-25)
    view.ResetCamera()
Render(view)
SaveScreenshot(out, view, ImageResolution=[1600, 700])
