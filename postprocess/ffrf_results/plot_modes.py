"""Mode shapes of one body from several ffrf results files, in the style of Fig. 3 of the paper.

One column per results file (an RC set), one row per mode. Each panel shows the exterior surface
of the tetrahedral mesh displaced by the mass-normalised mode shape, scaled so that the largest
nodal displacement is --amplitude (default 10%) of the body's bounding-box diagonal, coloured by
the displacement magnitude relative to its maximum and shaded by a head light. Every panel uses
the same view angle; the panels of a column share their axis limits. A file whose run did not
complete is an error.

    ffrf-plot-modes crank_rc1.h5 crank_rc2.h5 crank_rc3.h5 -o modes.png --modes 2 --body crank

(ffrf-plot-modes is the console script of `pip install ./postprocess`;
postprocess/plot_modes.py runs the same code.)
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.cm import ScalarMappable  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

import ffrf_results  # noqa: E402


def read_file(path, body, num_modes):
    """What one column needs: label, coordinates, surface triangles, shapes, frequencies."""
    with ffrf_results.open_results(path) as results:
        name = results.body(body)
        return {
            "label": results.label(name),
            "body": name,
            "xyz": results.coordinates(name),
            "triangles": results.surface_triangles(name),
            "shapes": results.shapes(name)[:num_modes],
            "frequencies": results.frequencies(name)[:num_modes],
        }


def view_direction(elev, azim):
    """Unit vector from the scene towards the viewer for matplotlib's (elev, azim), degrees."""
    e, a = np.radians(elev), np.radians(azim)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def draw_panel(ax, xyz, triangles, displacement, amplitude, colormap, light):
    """Draw the displaced, coloured surface; return the displaced points."""
    magnitude = np.linalg.norm(displacement, axis=1)
    largest = magnitude.max() if magnitude.size else 0.0
    size = np.linalg.norm(xyz.max(axis=0) - xyz.min(axis=0))
    scale = amplitude * size / largest if largest > 0.0 else 0.0
    points = xyz + scale * displacement
    corners = points[triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    lengths = np.linalg.norm(normals, axis=1)
    normals /= np.where(lengths > 0.0, lengths, 1.0)[:, None]
    shade = 0.45 + 0.55 * np.abs(normals @ light)
    relative = magnitude[triangles].mean(axis=1) / largest if largest > 0.0 else \
        np.zeros(len(triangles))
    colours = colormap(relative)
    colours[:, :3] *= shade[:, None]
    ax.add_collection3d(Poly3DCollection(corners, facecolors=colours, edgecolors="none"))
    return points


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="results files (.h5), one column each")
    parser.add_argument("-o", "--output", required=True, help="image file (PNG, PDF, SVG)")
    parser.add_argument("--modes", type=int, default=3, help="modes to show, rows (default 3)")
    parser.add_argument("--body", help="body name (default: the first body of each file)")
    parser.add_argument("--amplitude", type=float, default=0.1,
                        help="largest displacement drawn, fraction of the body size (0.1)")
    parser.add_argument("--elev", type=float, default=25.0, help="view elevation, degrees")
    parser.add_argument("--azim", type=float, default=-60.0, help="view azimuth, degrees")
    parser.add_argument("--dpi", type=int, default=150, help="resolution of raster output")
    args = parser.parse_args(argv)
    if args.modes < 1:
        parser.error(f"--modes {args.modes}: must be at least 1")
    try:
        columns = [read_file(path, args.body, args.modes) for path in args.files]
    except ffrf_results.ResultsError as exc:
        return ffrf_results.command_error("plot_modes.py", exc)

    colormap = plt.get_cmap("viridis")
    light = view_direction(args.elev, args.azim)
    num_cols = len(columns)
    fig = plt.figure(figsize=(3.6 * num_cols + 0.8, 3.0 * args.modes + 0.6))
    body = ", ".join(dict.fromkeys(column["body"] for column in columns))
    fig.suptitle(f"Mode shapes of {body} (largest displacement drawn at "
                 f"{100 * args.amplitude:g}% of its size)", fontsize=11)
    for col, column in enumerate(columns):
        xyz = column["xyz"]
        size = np.linalg.norm(xyz.max(axis=0) - xyz.min(axis=0))
        margin = args.amplitude * size
        low, high = xyz.min(axis=0) - margin, xyz.max(axis=0) + margin
        for row in range(args.modes):
            ax = fig.add_subplot(args.modes, num_cols, row * num_cols + col + 1,
                                 projection="3d")
            ax.set_axis_off()
            if row >= len(column["frequencies"]):
                ax.set_title(f"{column['label']}\nmode {row + 1}: not computed", fontsize=9)
                continue
            draw_panel(ax, xyz, column["triangles"], column["shapes"][row], args.amplitude,
                       colormap, light)
            ax.set_xlim(low[0], high[0])
            ax.set_ylim(low[1], high[1])
            ax.set_zlim(low[2], high[2])
            ax.set_box_aspect(high - low, zoom=1.3)
            ax.view_init(elev=args.elev, azim=args.azim)
            ax.set_title(f"{column['label']}\nmode {row + 1}: "
                         f"{column['frequencies'][row]:.1f} Hz", fontsize=9)
    fig.subplots_adjust(left=0.0, right=0.88, bottom=0.02, top=0.9, wspace=0.02, hspace=0.15)
    bar_axes = fig.add_axes([0.9, 0.15, 0.02, 0.65])
    fig.colorbar(ScalarMappable(Normalize(0.0, 1.0), colormap), cax=bar_axes,
                 label="|u| / max |u|")
    fig.savefig(args.output, dpi=args.dpi)
    plt.close(fig)
    print(f"plot_modes.py: wrote {args.output} ({num_cols} files x {args.modes} modes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
