"""Plot every sensor of a results file (/sensors/<name>, docs/sensors.md) against time: one
panel per sensor, one line per value (x, y, z; the 9 axes of an orientation; the 12 reaction
components; kinetic and strain energy), labelled with the sensor's type, unit and what it
measures. Optionally a CSV of all sensors.

    ffrf-plot-sensors RESULTS.h5 [--output sensors.png] [--csv sensors.csv] [--only NAME ...]

(ffrf-plot-sensors is the console script of `pip install ./postprocess`;
postprocess/plot_sensors.py runs the same code.)
"""
import argparse
import math
import sys

import numpy as np

import ffrf_results

COMPONENTS = {
    3: ["x", "y", "z"],
    9: ["x_x", "x_y", "x_z", "y_x", "y_y", "y_z", "z_x", "z_y", "z_z"],
    12: ["F1x", "F1y", "F1z", "M1x", "M1y", "M1z", "F2x", "F2y", "F2z", "M2x", "M2y", "M2z"],
    2: ["kinetic", "strain"],
    1: [""],
}
#: names of the values of sensor types whose values are not x, y, z
TYPE_COMPONENTS = {"driver": ["coordinate", "rate", "torque"]}


def read_sensors(file_name, only=None):
    """[(name, attributes, values (num_steps x k))] and the time t (a run that did not
    complete is read as far as it got)."""
    with ffrf_results.open_results(file_name, require_complete=False) as results:
        f = results.file
        if "sensors" not in f:
            return np.array(f["/time/t"][()]), []
        t = np.array(f["/time/t"][()])
        sensors = []
        for name in f["/sensors"]:
            if only and name not in only:
                continue
            data = np.array(f["/sensors/" + name][()])
            if data.ndim == 1:
                data = data[:, None]
            attrs = {k: ffrf_results.text(v) for k, v in f["/sensors/" + name].attrs.items()}
            sensors.append((name, attrs, data))
    return t, sensors


def labels(size, kind=""):
    if kind in TYPE_COMPONENTS and len(TYPE_COMPONENTS[kind]) == size:
        return TYPE_COMPONENTS[kind]
    return COMPONENTS.get(size, [str(k) for k in range(size)])


def write_csv(file_name, t, sensors):
    header = ["t"]
    columns = [t]
    for name, attrs, data in sensors:
        for k, label in enumerate(labels(data.shape[1], attrs.get("type", ""))):
            header.append(name + ("." + label if label else ""))
            columns.append(data[:, k])
    np.savetxt(file_name, np.column_stack(columns), delimiter=",", header=",".join(header),
               comments="")


def plot(file_name, t, sensors, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(sensors)
    cols = 2 if n > 1 else 1
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(6.5 * cols, 2.6 * rows), squeeze=False,
                             sharex=True)
    for ax, (name, attrs, data) in zip(axes.flat, sensors):
        for k, label in enumerate(labels(data.shape[1], attrs.get("type", ""))):
            ax.plot(t, data[:, k], lw=1.0, label=label or None)
        what = ", ".join(attrs[key] for key in ("body", "marker", "joint") if key in attrs)
        ax.set_title("%s: %s%s" % (name, attrs.get("type", "?"), " (%s)" % what if what else ""),
                     fontsize=9)
        ax.set_ylabel(attrs.get("units", ""))
        if 1 < data.shape[1] <= 12:
            ax.legend(fontsize=6, ncol=min(data.shape[1], 6))
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(file_name, dpi=120)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", help="results file (.h5) of a mechanism run")
    parser.add_argument("--output", default=None, help="image (default: <results>_sensors.png)")
    parser.add_argument("--csv", default=None, help="also write the sensors as CSV")
    parser.add_argument("--only", nargs="*", default=None, help="sensor names to plot")
    args = parser.parse_args(argv)
    try:
        t, sensors = read_sensors(args.results, args.only)
    except ffrf_results.ResultsError as exc:
        return ffrf_results.command_error("plot_sensors.py", exc)
    if not sensors:
        print("plot_sensors: %s has no sensors (add &sensor groups to the case)" % args.results,
              file=sys.stderr)
        return 1
    if args.csv:
        write_csv(args.csv, t, sensors)
    output = args.output or args.results.rsplit(".", 1)[0] + "_sensors.png"
    plot(output, t, sensors, args.results)
    print("plot_sensors: %d sensors -> %s" % (len(sensors), output))
    return 0


if __name__ == "__main__":
    sys.exit(main())
