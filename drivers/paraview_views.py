"""The standard views of a BeamContact run in ParaView, saved as PNG: the beams deformed (Warp By Vector
on `displacement`, coloured by its magnitude) with the contact forces on beam B as arrows (Glyph of
`contact force`, scaled so that the largest is a quarter of the model's size), each from three
directions: iso (the render script's default camera, elevation 22 and azimuth -60 degrees), xz (from
the -Y side, looking at the XZ plane) and xy (from above, looking down -Z).

    pvpython share/beamcontact/paraview_views.py RESULTS_DIR OUT_DIR [--stages 1] [--views iso,xz,xy]
                                                 [--size 1600x1200]

Reads RESULTS_DIR/results.pvd (the beams) and, where the run wrote it, contact.pvd (the contact
points, their own series); for each stage T the step whose load factor is nearest; writes
OUT_DIR/<view>_T<T>.png for each view and stage and prints each file's path. Needs ParaView's Python
(pvpython, from the Debian package paraview; run without it: one line naming the package, exit 4);
a display for its renderer (on a machine without one: xvfb-run -a pvpython ...). Usage errors: one
line, exit 1.

In the ParaView window the same is: File > Open results.pvd and contact.pvd, Apply; select results.pvd,
Filters > Warp By Vector (Vectors: displacement, Scale Factor 1), Apply, colour by displacement; select
contact.pvd, Warp By Vector the same way, then Glyph (Glyph Type Arrow, Orientation Array and Scale
Array: contact force, Glyph Mode: All Points, Scale Factor as below), Apply; the time control picks the
step (README, "Opening results in ParaView").
"""
import argparse
import math
import os
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from python_modules import need  # noqa: E402

VIEWS = {  # camera direction (from the camera to the model) and view-up
    "iso": None,  # from elevation and azimuth, below
    "xz": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "xy": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
}
ELEVATION, AZIMUTH = 22.0, -60.0  # degrees, as render_stages.py's default view


def fail(message):
    print(f"beamcontact: paraview views: {message}", file=sys.stderr)
    sys.exit(1)


def arguments():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("out")
    ap.add_argument("--stages", default="1", help="load factors, one set of views each (default 1)")
    ap.add_argument("--views", default="iso,xz,xy", help="which of iso, xz, xy (default all three)")
    ap.add_argument("--size", default="1600x1200", help="pixels, WIDTHxHEIGHT (default 1600x1200)")
    a = ap.parse_args()
    try:
        a.stages = [float(s) for s in a.stages.split(",")]
        a.size = [int(v) for v in a.size.lower().split("x")]
    except ValueError:
        fail(f"--stages takes numbers like 0.5,1 and --size WIDTHxHEIGHT; got {a.stages!r} and {a.size!r}")
    a.views = a.views.split(",")
    unknown = [v for v in a.views if v not in VIEWS]
    if unknown or len(a.size) != 2 or min(a.size) < 16:
        fail(f"--views takes {', '.join(VIEWS)} and --size two numbers of at least 16; got {a.views} and {a.size}")
    if not os.path.isfile(os.path.join(a.results, "results.pvd")):
        fail(f"{os.path.join(a.results, 'results.pvd')} does not exist (is {a.results} a results directory written "
             "with VTK output?)")
    if not os.path.isdir(a.out):
        fail(f"{a.out} is not a directory")
    return a


def timesteps(pvd):
    return sorted({float(d.get("timestep")) for d in ET.parse(pvd).getroot().iter("DataSet")})


def main():
    a = arguments()
    pv = need("paraview.simple", "paraview views", "; run this script with pvpython")
    pvd = os.path.join(a.results, "results.pvd")
    contact_pvd = os.path.join(a.results, "contact.pvd")
    times = timesteps(pvd)
    if not times:
        fail(f"{pvd} lists no step")
    chosen = [min(times, key=lambda t: abs(t - s)) for s in a.stages]

    view = pv.CreateRenderView()
    view.ViewSize = a.size
    view.OrientationAxesVisibility = 1
    beams = pv.OpenDataFile(pvd)
    warp = pv.WarpByVector(Input=beams)
    warp.Vectors = ["POINTS", "displacement"]
    warp.ScaleFactor = 1.0
    shown = pv.Show(warp, view)
    pv.ColorBy(shown, ("POINTS", "displacement", "Magnitude"))
    shown.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(pv.GetColorTransferFunction("displacement"), view)
    bar.Title, bar.ComponentTitle = "|displacement| (model units)", ""

    glyph = None
    if os.path.isfile(contact_pvd) and timesteps(contact_pvd):
        contact = pv.OpenDataFile(contact_pvd)
        contact_warp = pv.WarpByVector(Input=contact)
        contact_warp.Vectors = ["POINTS", "displacement"]
        contact_warp.ScaleFactor = 1.0
        glyph = pv.Glyph(Input=contact_warp, GlyphType="Arrow")
        glyph.OrientationArray = ["POINTS", "contact force"]
        glyph.ScaleArray = ["POINTS", "contact force"]
        glyph.GlyphMode = "All Points"
        arrows = pv.Show(glyph, view)
        pv.ColorBy(arrows, None)
        arrows.AmbientColor = arrows.DiffuseColor = [0.86, 0.08, 0.24]  # crimson, as render's arrows

    # The arrows' scale: the largest contact force over the chosen steps is a quarter of the model's
    # largest extent (as in beamcontact render).
    span, fmax = 0.0, 0.0
    for t in chosen:
        warp.UpdatePipeline(t)
        b = warp.GetDataInformation().GetBounds()
        span = max(span, b[1] - b[0], b[3] - b[2], b[5] - b[4])
        if glyph is not None:
            contact_warp.UpdatePipeline(t)
            array = contact_warp.PointData["contact force"] if "contact force" in contact_warp.PointData.keys() \
                else None
            if array is not None:
                fmax = max(fmax, array.GetRange(-1)[1])
    if glyph is not None:
        glyph.ScaleFactor = 0.25 * span / fmax if fmax > 0 else 0.0

    for t in chosen:
        view.ViewTime = t
        for name in a.views:
            if VIEWS[name] is None:
                el, az = math.radians(ELEVATION), math.radians(AZIMUTH)
                direction = (-math.cos(el) * math.cos(az), -math.cos(el) * math.sin(az), -math.sin(el))
                up = (0.0, 0.0, 1.0)
            else:
                direction, up = VIEWS[name]
            view.CameraPosition = [-d for d in direction]
            view.CameraFocalPoint = [0.0, 0.0, 0.0]
            view.CameraViewUp = list(up)
            pv.ResetCamera(view)
            pv.Render(view)
            path = os.path.join(a.out, f"{name}_T{t:g}.png")
            pv.SaveScreenshot(path, view, ImageResolution=a.size)
            print(f"paraview views: {path}")


if __name__ == "__main__":
    try:
        main()
    except SystemExit:
        raise
    except Exception as e:  # noqa: BLE001 - reported as one line, not a traceback
        print(f"beamcontact: paraview views: {type(e).__name__}: {e}", file=sys.stderr)
        sys.exit(3)
