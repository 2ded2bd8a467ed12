"""Render a dipc-surface file (.vtp, or .vtm with one block per body) to a PNG with ParaView.

    pvbatch bench/render_surface.py SURFACE.vtm|SURFACE.vtp OUT.png [--title TEXT] [--size W H]

Where there is no display, run it under a virtual one: `xvfb-run -a pvbatch ...` (Debian's
ParaView has no offscreen-only build). Each quad is coloured by its body id; a floor patch is
drawn at the lowest point of the surface, the camera looks from above one corner of the
bounding box. Meant for the README's pictures of big runs (docs/performance.md names the runs).
"""
import argparse

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction, Plane,
                             SaveScreenshot, Show, Text, XMLMultiBlockDataReader, XMLPolyDataReader)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("surface")
    parser.add_argument("png")
    parser.add_argument("--title", default="")
    parser.add_argument("--size", type=int, nargs=2, default=[1600, 1000])
    args = parser.parse_args()

    reader = (XMLMultiBlockDataReader if args.surface.endswith(".vtm") else XMLPolyDataReader)(FileName=[args.surface])
    reader.UpdatePipeline()
    xmin, xmax, ymin, ymax, zmin, zmax = reader.GetDataInformation().GetBounds()
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = args.size
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0

    display = Show(reader, view)
    ColorBy(display, ("CELLS", "body"))
    lut = GetColorTransferFunction("body")
    lut.ApplyPreset("Rainbow Uniform", True)
    display.SetScalarBarVisibility(view, False)

    # A floor one and a half times the footprint of the bodies, just below them (the scenes' contact plane).
    cx, cy = 0.5 * (xmin + xmax), 0.5 * (ymin + ymax)
    w = 0.75 * max(xmax - xmin, ymax - ymin)
    floor = Plane(Origin=[cx - w, cy - w, zmin], Point1=[cx + w, cy - w, zmin], Point2=[cx - w, cy + w, zmin])
    floor_display = Show(floor, view)
    floor_display.DiffuseColor = [0.75, 0.75, 0.75]
    floor_display.AmbientColor = [0.75, 0.75, 0.75]

    if args.title:
        text = Text(Text=args.title)
        text_display = Show(text, view)
        text_display.FontSize = 22
        text_display.Color = [0, 0, 0]
        text_display.WindowLocation = "Upper Left Corner"

    h = zmax - zmin
    view.CameraFocalPoint = [cx, cy, zmin + 0.4 * h]
    view.CameraPosition = [cx + 1.6 * w, cy - 2.0 * w, zmin + 1.6 * h + 0.8 * w]
    view.CameraViewUp = [0, 0, 1]
    view.ResetCamera(False)
    SaveScreenshot(args.png, view, ImageResolution=args.size)
    print("render_surface: %s -> %s (%d x %d)" % (args.surface, args.png, args.size[0], args.size[1]))


if __name__ == "__main__":
    main()
