# Renders the eccentric mouth from above (cases/cutter_head_eccentric.toml): left, the axial velocity
# of the water 2.4 cm under the back plate (the mouth, at rest, is where it leaves; blocked blade
# cells are white); right, the DEM walls with the back plate and its mouth cut out.
# usage: xvfb-run -a pvbatch docs/render_eccentric_mouth.py RESULTS_DIR OUT.png
from paraview.simple import *
import sys, glob
results, out = sys.argv[1], sys.argv[2]
fluid = XMLUnstructuredGridReader(FileName=[sorted(glob.glob(results + '/vtk/fluid_*.vtu'))[-1]])
walls = XMLPolyDataReader(FileName=[sorted(glob.glob(results + '/vtk/walls_*.vtp'))[-1]])
rotor = Threshold(Input=fluid); rotor.Scalars = ['CELLS', 'zone']; rotor.LowerThreshold = 0; rotor.UpperThreshold = 0
sl = Slice(Input=rotor); sl.SliceType = 'Plane'; sl.SliceType.Origin = [0, 0, -0.024]; sl.SliceType.Normal = [0, 0, 1]
calc = Calculator(Input=sl); calc.AttributeType = 'Cell Data'; calc.ResultArrayName = 'u_z'; calc.Function = 'velocity_Z'
view = CreateView('RenderView'); view.ViewSize = [1400, 700]
try:
    view.OrientationAxesVisibility = 0
except Exception: pass
try:
    view.UseColorPaletteForBackground = 0
except Exception: pass
view.Background = [1, 1, 1]
layout = CreateLayout('m'); AssignViewToLayout(view=view, layout=layout)
d1 = Show(calc, view); ColorBy(d1, ('CELLS', 'u_z'))
lut = GetColorTransferFunction('u_z'); lut.ApplyPreset('Cool to Warm', True); lut.RescaleTransferFunction(-3.0, 3.0)
d1.SetScalarBarVisibility(view, True)
bar = GetScalarBar(lut, view); bar.Title = 'u_z [m/s], 2.4 cm under the plate'; bar.ComponentTitle = ''; bar.TitleColor=[0,0,0]; bar.LabelColor=[0,0,0]
tr = Transform(Input=walls); tr.Transform.Translate = [1.0, 0, 0]
# the back plate is the last wall; the turning walls (blades, ring, hub, shaft) in grey below it
last = int(walls.CellData['wall'].GetRange()[1])
plate = Threshold(Input=tr); plate.Scalars = ['CELLS', 'wall']; plate.LowerThreshold = last; plate.UpperThreshold = last
turning = Threshold(Input=tr); turning.Scalars = ['CELLS', 'wall']; turning.LowerThreshold = 0; turning.UpperThreshold = last - 1
d3 = Show(turning, view); d3.DiffuseColor = [0.6, 0.6, 0.65]; d3.ColorArrayName = [None, '']
d2 = Show(plate, view); d2.SetRepresentationType('Surface With Edges'); d2.DiffuseColor = [0.85, 0.6, 0.4]; d2.EdgeColor = [0.3, 0.2, 0.1]; d2.ColorArrayName = [None, '']
view.CameraPosition = [0.5, 0, 3.0]; view.CameraFocalPoint = [0.5, 0, 0]; view.CameraViewUp = [0, 1, 0]
Render(view)
view.CameraPosition = [0.5, 0, 3.0]; view.CameraFocalPoint = [0.5, 0, 0]; view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 1; view.CameraParallelScale = 0.5
Render(view)
SaveScreenshot(out, view, ImageResolution=[1400, 700])
