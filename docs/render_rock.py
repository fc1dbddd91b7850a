# Renders where the default head's rock goes: the particles (spheres) inside the DEM walls
# (wireframe) at four times of the run (its start, a fifth, half and end of the frames), seen from the side with the axis drawn upward (the ring
# at the top of the picture; in the shipped cases gravity pulls toward the ring, README "Which
# way the ladder leans").
# usage: xvfb-run -a pvbatch docs/render_rock.py RESULTS_DIR OUT.png
# (RESULTS_DIR from `spillage run cases/cutter_head.toml`)
from paraview.simple import *
import sys, glob
results, out = sys.argv[1], sys.argv[2]
parts = sorted(glob.glob(results + '/vtk/particles_*'))
walls = sorted(glob.glob(results + '/vtk/walls_*'))
def read(path):
    return XMLPolyDataReader(FileName=[path]) if path.endswith('.vtp') else XMLUnstructuredGridReader(FileName=[path])
picks = [0, len(parts) // 5, len(parts) // 2, len(parts) - 1]
panels = []
for k, i in enumerate(picks):
    v = CreateView('RenderView'); v.ViewSize = [500, 620]
    try: v.UseColorPaletteForBackground = 0
    except Exception: pass
    v.Background = [1, 1, 1]
    try: v.OrientationAxesVisibility = 0
    except Exception: pass
    # the walls are written on the same steps as the particles
    w = read(walls[min(i, len(walls) - 1)])
    g = Glyph(Input=read(parts[i]), GlyphType='Sphere'); g.ScaleFactor = 0.02; g.GlyphMode = 'All Points'
    try: g.ScaleArray = ['POINTS', 'No scale array']
    except Exception: pass
    dw = Show(w, v); dw.SetRepresentationType('Wireframe'); dw.AmbientColor = [0.5, 0.5, 0.5]; dw.DiffuseColor = [0.5, 0.5, 0.5]; dw.ColorArrayName = [None, '']; dw.Opacity = 0.3
    dg = Show(g, v); dg.DiffuseColor = [0.8, 0.3, 0.1]; dg.ColorArrayName = [None, '']
    Render(v)
    # the same camera in every panel (the first render resets it)
    v.CameraPosition = [0, -3, -0.2]; v.CameraFocalPoint = [0, 0, -0.2]; v.CameraViewUp = [0, 0, 1]
    v.CameraParallelProjection = 1; v.CameraParallelScale = 0.6
    Render(v)
    panel = out.replace('.png', f'_{k}.png')
    SaveScreenshot(panel, v, ImageResolution=[500, 620])
    panels.append(panel)
# side by side in one picture
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
from vtkmodules.vtkFiltersCore import vtkImageAppend
append = vtkImageAppend(); append.SetAppendAxis(0)
for panel in panels:
    r = vtkPNGReader(); r.SetFileName(panel); r.Update(); append.AddInputData(r.GetOutput())
append.Update()
writer = vtkPNGWriter(); writer.SetFileName(out); writer.SetInputData(append.GetOutput()); writer.Write()
import os
for panel in panels:
    os.remove(panel)
