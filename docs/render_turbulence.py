# Renders a turbulent 2-D run near its lower wall: the last frame's velocity magnitude with
# streamlines (top) and the eddy viscosity nu_t (bottom), x in [X_MIN, X_MAX], y in [0, Y_MAX];
# checks that the k–ε fields are in the .vtu.
from paraview.simple import *
import sys, glob
# usage: xvfb-run -a pvbatch docs/render_turbulence.py RESULTS_DIR OUT.png [X_MIN X_MAX Y_MAX]
# (RESULTS_DIR from `spillage run cases/verification/turbulence/backward_facing_step.toml`)
results, out = sys.argv[1], sys.argv[2]
x_min, x_max, y_max = (float(v) for v in sys.argv[3:6]) if len(sys.argv) > 5 else (-2.0, 12.0, 3.0)
frame = sorted(glob.glob(results + '/vtk/fluid_*.vtu'))[-1]
fluid = XMLUnstructuredGridReader(FileName=[frame])
names = fluid.CellData.keys()
for needed in ['velocity', 'k', 'epsilon', 'nu_t', 'y_plus']:
    assert needed in names, needed + ' missing from ' + frame + ': ' + str(names)
box = Clip(Input=fluid); box.ClipType = 'Box'; box.ClipType.Position = [x_min, -1.0, -1.0]; box.ClipType.Length = [x_max - x_min, y_max + 1.0, 10.0]
box.Invert = 1
fluid = box
points = CellDatatoPointData(Input=fluid)
stream = StreamTracer(Input=points, SeedType='Line')
stream.Vectors = ['POINTS', 'velocity']
stream.SeedType.Point1 = [0.5, 0.02, 0.05]; stream.SeedType.Point2 = [0.5, y_max - 0.05, 0.05]; stream.SeedType.Resolution = 25
stream.MaximumStreamlineLength = 200.0
view = CreateView('RenderView'); view.ViewSize = [1600, 900]
try:
    view.UseColorPaletteForBackground = 0
except Exception: pass
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 0
d = Show(points, view); ColorBy(d, ('POINTS', 'velocity', 'Magnitude'))
lut = GetColorTransferFunction('velocity'); lut.ApplyPreset('Cool to Warm', True)
bar = GetScalarBar(lut, view); bar.Title = '|u| [m/s]'; bar.ComponentTitle = ''; bar.TitleColor = [0, 0, 0]; bar.LabelColor = [0, 0, 0]
bar.WindowLocation = 'Any Location'; bar.Position = [0.9, 0.55]; bar.ScalarBarLength = 0.35
# lifted in front of the slab's front face so that the surface does not hide them
lifted = Transform(Input=stream); lifted.Transform.Translate = [0, 0, 0.2]
ds = Show(lifted, view); ds.DiffuseColor = [0, 0, 0]; ds.ColorArrayName = [None, '']; ds.LineWidth = 1.5
nut = Transform(Input=fluid); nut.Transform.Translate = [0, -(y_max + 0.5), 0]
dn = Show(nut, view); ColorBy(dn, ('CELLS', 'nu_t'))
lut2 = GetColorTransferFunction('nu_t'); lut2.ApplyPreset('Viridis (matplotlib)', True)
lut2.RescaleTransferFunction(0.0, fluid.CellData['nu_t'].GetRange()[1])
bar2 = GetScalarBar(lut2, view); bar2.Title = 'nu_t [m²/s]'; bar2.ComponentTitle = ''; bar2.TitleColor = [0, 0, 0]; bar2.LabelColor = [0, 0, 0]
bar2.WindowLocation = 'Any Location'; bar2.Position = [0.9, 0.08]; bar2.ScalarBarLength = 0.35
cx, cy = 0.5 * (x_min + x_max), 0.5 * (y_max - (y_max + 0.5))
view.CameraPosition = [cx, cy, 60]; view.CameraFocalPoint = [cx, cy, 0]; view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 1; view.CameraParallelScale = 0.5 * (2 * y_max + 0.5) * 1.15
Render(view)
SaveScreenshot(out, view, ImageResolution=[1600, 900])
