"""Render a field of a PeriDeal run to a PNG with ParaView.

  xvfb-run -a pvpython render.py RUN.pvd OUT.png [options]

Loads the .pvd series, takes the last time step, moves every cell by its
displacement (Warp By Vector, scale 1: the deformed shape as it is), colors
the cells by Damage (blue = intact, red = fully damaged, as in the Peridigm
users' guide) or another field, and writes a PNG. The camera looks at the
centre of the deformed body from an oblique direction, with z up, and fits
the body in the picture. Options:
  --field NAME      the field to color by (default Damage, range 0 to 1);
                    NAME:x, :y, :z or :magnitude for a component of a vector
                    field, e.g. Displacement:x (range: the data's)
  --warp-scale S    magnify the displacement S times (default 1)
  --time T          the time step nearest to T instead of the last one
  --view X,Y,Z      direction from the body towards the camera (default 1,-1.6,0.9)
  --up X,Y,Z        the camera's up direction (default 0,0,1)
  --size W,H        image size in pixels (default 1200,900)
  --zoom Z          magnify the fitted view Z times (default 1.1)
  --title TEXT      a caption at the top left (default: the file name and time)
  --no-warp         draw the reference configuration instead of the deformed one
Debian's ParaView 5.11 (package paraview) renders through X only: without a
display run pvpython under xvfb-run (package xvfb); its
--force-offscreen-rendering ends in a segmentation fault there. If xvfb-run
-a aborts with "bad X server connection", an Xvfb left over from an earlier
failed run holds the display: end it, or pick a display with -n.
"""

import argparse
import os

from paraview.simple import (ColorBy, GetColorTransferFunction, GetScalarBar,
                             CreateView, PVDReader, Render, SaveScreenshot,
                             Show, Text, WarpByVector, UpdatePipeline)

parser = argparse.ArgumentParser(
    description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("pvd")
parser.add_argument("png")
parser.add_argument("--time", type=float, default=None)
parser.add_argument("--view", default="1,-1.6,0.9")
parser.add_argument("--up", default="0,0,1")
parser.add_argument("--size", default="1200,900")
parser.add_argument("--title", default=None)
parser.add_argument("--no-warp", action="store_true")
parser.add_argument("--field", default="Damage")
parser.add_argument("--warp-scale", type=float, default=1.0)
parser.add_argument("--zoom", type=float, default=1.1)
args = parser.parse_args()


def triple(text):
    values = [float(v) for v in text.split(",")]
    if len(values) != 3:
        raise SystemExit("Error: expected x,y,z, got '%s'" % text)
    return values


if not os.path.isfile(args.pvd):
    raise SystemExit("Error: cannot open '%s'" % args.pvd)

reader = PVDReader(FileName=os.path.abspath(args.pvd))
times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
if args.time is None:
    time = times[-1]
else:
    time = min(times, key=lambda t: abs(t - args.time))
reader.UpdatePipeline(time)

# deal.II 9.4 writes cell data (one value per point) as point data on
# patches of their own, constant over each cell; accept either.
field, _, component = args.field.partition(":")
components = {"": None, "x": "X", "y": "Y", "z": "Z", "magnitude": "Magnitude"}
if component not in components:
    raise SystemExit("Error: --field %s: the component must be x, y, z or magnitude"
                     % args.field)
cell_arrays = reader.CellData.keys()
point_arrays = reader.PointData.keys()
if field in cell_arrays:
    association = "CELLS"
elif field in point_arrays:
    association = "POINTS"
else:
    raise SystemExit("Error: '%s' has no %s field: add it to Output/Variables"
                     % (args.pvd, field))

source = reader
if not args.no_warp:
    if "Displacement" not in point_arrays:
        raise SystemExit("Error: '%s' has no Displacement field: add it to "
                         "Output/Variables or use --no-warp" % args.pvd)
    source = WarpByVector(Input=reader)
    source.Vectors = ["POINTS", "Displacement"]
    source.ScaleFactor = args.warp_scale
UpdatePipeline(time=time, proxy=source)

width, height = [int(v) for v in args.size.split(",")]
view = CreateView("RenderView")
view.ViewSize = [width, height]
view.ViewTime = time
view.OrientationAxesVisibility = 1
view.Background = [1.0, 1.0, 1.0]
try:  # ParaView >= 5.10 uses a palette unless told otherwise
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass

display = Show(source, view)
if components[component] is None:
    ColorBy(display, (association, field))
else:
    ColorBy(display, (association, field, components[component]))
lut = GetColorTransferFunction(field)
lut.ApplyPreset("Jet", True)
bar = GetScalarBar(lut, view)
bar.Title = field if components[component] is None else "%s %s" % (field, component)
bar.ComponentTitle = ""
bar.TitleColor = [0, 0, 0]
bar.LabelColor = [0, 0, 0]
if field == "Damage":
    lut.RescaleTransferFunction(0.0, 1.0)
    lut.AutomaticRescaleRangeMode = "Never"
    bar.AutomaticLabelFormat = 0
    bar.LabelFormat = "%-#4.1f"
    bar.RangeLabelFormat = "%-#4.1f"
else:
    display.RescaleTransferFunctionToDataRange(False, True)
bar.Visibility = 1
display.SetScalarBarVisibility(view, True)

title = args.title
if title is None:
    title = "%s   t = %.4g s" % (os.path.basename(args.pvd), time)
    if args.warp_scale != 1 and not args.no_warp:
        title += "   (displacement x %g)" % args.warp_scale
text = Text(Text=title)
text_display = Show(text, view)
text_display.Color = [0, 0, 0]
text_display.FontSize = 14
text_display.WindowLocation = "Upper Left Corner"

# The first render resets the camera: render once before placing it.
Render(view)

# Camera: look at the centre of the deformed body from args.view.
bounds = source.GetDataInformation().GetBounds()
center = [0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
          0.5 * (bounds[4] + bounds[5])]
direction = triple(args.view)
norm = sum(d * d for d in direction) ** 0.5
diagonal = sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)) ** 0.5
camera = view.GetActiveCamera()
camera.SetFocalPoint(center)
camera.SetPosition([c + 3 * diagonal * d / norm for c, d in zip(center, direction)])
camera.SetViewUp(triple(args.up))
view.ResetCamera(False)
camera.Zoom(args.zoom)

Render(view)
SaveScreenshot(args.png, view, ImageResolution=[width, height])
print("wrote %s (t = %g of %d time steps, %s)" % (args.png, time, len(times),
                                                  "deformed" if not args.no_warp else "reference"))
