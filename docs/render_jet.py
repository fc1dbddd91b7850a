# Renders the last frame of a jet-impingement run whose fluid mesh follows the receding plate
# ([wear.fluid_mesh]): the water's speed on the mesh (its edges show the cells bent into the
# crater), the grains as dots, and a close-up of the crater.
# usage: xvfb-run -a pvbatch docs/render_jet.py RESULTS_DIR OUT.png [--zoom Y0,Y1]
#   --zoom Y0,Y1   the close-up shows the plate's side of the water between y = Y0 and Y1
from paraview.simple import *
import sys, glob
args = sys.argv[1:]
results, out = args[0], args[1]
options = dict(zip(args[2::2], args[3::2]))
fluid = XMLUnstructuredGridReader(FileName=[sorted(glob.glob(results + '/vtk/fluid_*.vtu'))[-1]])
particles = XMLPolyDataReader(FileName=[sorted(glob.glob(results + '/vtk/particles_*.vtp'))[-1]])
speed = Calculator(Input=fluid); speed.AttributeType = 'Cell Data'; speed.ResultArrayName = 'speed'; speed.Function = 'mag(velocity)'

def panel(view, show_edges):
    try:
        view.UseColorPaletteForBackground = 0
    except Exception:
        pass
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 0
    d = Show(speed, view); d.SetRepresentationType('Surface With Edges' if show_edges else 'Surface')
    d.EdgeColor = [0.35, 0.35, 0.35]
    ColorBy(d, ('CELLS', 'speed'))
    lut = GetColorTransferFunction('speed'); lut.ApplyPreset('Viridis (matplotlib)', True)
    d.RescaleTransferFunctionToDataRange(True, False)
    bar = GetScalarBar(lut, view); bar.Title = 'water speed [m/s]'; bar.ComponentTitle = ''; bar.Visibility = 1
    bar.TitleColor = [0, 0, 0]; bar.LabelColor = [0, 0, 0]
    p = Show(particles, view); p.SetRepresentationType('Points'); p.PointSize = 7; p.AmbientColor = [1, 0.3, 0.1]; p.DiffuseColor = [1, 0.3, 0.1]
    return d

layout = CreateLayout('jet')
whole = CreateView('RenderView'); AssignViewToLayout(view=whole, layout=layout)
panel(whole, False)
whole.ResetCamera()
cam = whole.GetActiveCamera(); cam.SetViewUp(0, 1, 0)
close = CreateView('RenderView'); layout.SplitHorizontal(0, 0.4); AssignViewToLayout(view=close, layout=layout, hint=2)
panel(close, True)
bounds = fluid.GetDataInformation().GetBounds()
y0, y1 = [float(v) for v in options.get('--zoom', '%g,%g' % (bounds[2], bounds[3])).split(',')]
x1 = bounds[1]; width = y1 - y0
close.CameraPosition = [x1 - 0.25 * width, 0.5 * (y0 + y1), 1.0]
close.CameraFocalPoint = [x1 - 0.25 * width, 0.5 * (y0 + y1), 0.0]
close.CameraViewUp = [0, 1, 0]
close.CameraParallelProjection = 1
close.CameraParallelScale = 0.5 * width
whole.CameraParallelProjection = 1
layout.SetSize(1800, 900)
SaveScreenshot(out, layout, ImageResolution=[1800, 900])
