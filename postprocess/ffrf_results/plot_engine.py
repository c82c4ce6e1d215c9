"""Crank angular speed of several ffrf engine runs on one chart, with a zoom on the regime.

Top panel: the crank speed of every run (one curve per file, labelled by the rc_set and mpc
attributes of /engine) over the whole simulated time, rpm on the right axis, the zoom window
shaded. Bottom panel: the zoom on the regime oscillations, by default the last 0.2 s or the last
two engine cycles (4 pi of crank angle each) of the first file, whichever is shorter, with the
engine cycle boundaries of the first file dotted; --zoom T0 T1 picks the window in seconds.
--pressure FILE also draws the in-cylinder pressure (bar) against the crank angle of the cycle
(0 .. 720 deg, 0 = TDC at the start of intake) over the last complete cycle of the first file.
A run whose status is not 'complete' is an error unless --allow-incomplete (then its label
says so and its curve ends where the run stopped).

    ffrf-plot-engine engine_rigid.h5 engine_rc1.h5 engine_rc2.h5 -o speed.png --pressure p.png

(ffrf-plot-engine is the console script of `pip install ./postprocess`;
postprocess/plot_engine.py runs the same code.)
"""
import argparse
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import ffrf_results  # noqa: E402

RPM = 30.0 / math.pi   # rpm per rad/s
ZOOM_SECONDS = 0.2
ZOOM_CYCLES = 2


def default_zoom(run):
    """(t0, t1): the last ZOOM_SECONDS or the last ZOOM_CYCLES engine cycles of a run,
    whichever is shorter (the whole run if it is shorter still)."""
    t_end = float(run.t[-1])
    theta_start = float(run.crank_angle[-1]) - ZOOM_CYCLES * ffrf_results.ENGINE_CYCLE
    t_cycles = float(run.t[0])
    if theta_start > float(np.min(run.crank_angle)):
        _, times = ffrf_results.window_samples(run.crank_angle, run.t, theta_start,
                                               float(run.crank_angle[-1]))
        t_cycles = float(times[0])
    return max(t_end - ZOOM_SECONDS, t_cycles, float(run.t[0])), t_end


def cycle_starts(run, t0, t1):
    """Times in [t0, t1] at which the crank angle of a run passes a multiple of 4 pi."""
    cycle = np.floor(run.crank_angle / ffrf_results.ENGINE_CYCLE)
    times = []
    for k in np.flatnonzero(np.diff(cycle) > 0):
        target = cycle[k + 1] * ffrf_results.ENGINE_CYCLE
        w = (target - run.crank_angle[k]) / (run.crank_angle[k + 1] - run.crank_angle[k])
        time = run.t[k] + w * (run.t[k + 1] - run.t[k])
        if t0 <= time <= t1:
            times.append(time)
    return times


def add_rpm_axis(ax):
    rpm_axis = ax.secondary_yaxis("right", functions=(lambda w: w * RPM, lambda n: n / RPM))
    rpm_axis.set_ylabel("crank speed (rpm)")


def plot_speed(runs, zoom, output, dpi):
    fig, (whole, detail) = plt.subplots(2, 1, figsize=(9.0, 8.0))
    t0, t1 = zoom
    low, high = math.inf, -math.inf
    for run in runs:
        whole.plot(run.t, run.crank_speed, linewidth=1.0, label=run.label)
        detail.plot(run.t, run.crank_speed, linewidth=1.2, label=run.label)
        inside = (run.t >= t0) & (run.t <= t1)
        if inside.any():
            low = min(low, float(run.crank_speed[inside].min()))
            high = max(high, float(run.crank_speed[inside].max()))
    whole.axvspan(t0, t1, color="0.85", zorder=0, label="zoom below")
    whole.set_xlim(min(float(run.t[0]) for run in runs), max(float(run.t[-1]) for run in runs))
    whole.set_xlabel("time (s)")
    whole.set_ylabel("crank speed (rad/s)")
    whole.set_title("Crank angular speed")
    whole.grid(True, linewidth=0.4)
    whole.legend(loc="lower right", fontsize=8)
    add_rpm_axis(whole)
    for time in cycle_starts(runs[0], t0, t1):
        detail.axvline(time, color="0.5", linestyle=":", linewidth=0.8)
    detail.set_xlim(t0, t1)
    if math.isfinite(low):
        margin = 0.08 * (high - low) if high > low else 0.01 * max(abs(high), 1.0)
        detail.set_ylim(low - margin, high + margin)
    detail.set_xlabel("time (s)")
    detail.set_ylabel("crank speed (rad/s)")
    detail.set_title(f"Regime, {t0:.3f} .. {t1:.3f} s (dotted: engine cycle starts, 720 deg, "
                     f"of {runs[0].label})", fontsize=10)
    detail.grid(True, linewidth=0.4)
    add_rpm_axis(detail)
    fig.tight_layout()
    fig.savefig(output, dpi=dpi)
    plt.close(fig)


def plot_pressure(run, output, dpi):
    """Pressure over the last complete engine cycle of `run`; ResultsError if it has none."""
    if run.pressure is None:
        raise ffrf_results.ResultsError(f"{run.path}: no /time/pressure to plot")
    try:
        theta_a, theta_b = ffrf_results.cycle_window(run.crank_angle, 1)
    except ffrf_results.ResultsError as exc:
        raise ffrf_results.ResultsError(f"{run.path}: {exc}") from exc
    theta, pressure = ffrf_results.window_samples(run.crank_angle, run.pressure, theta_a, theta_b)
    _, times = ffrf_results.window_samples(run.crank_angle, run.t, theta_a, theta_b)
    degrees = np.degrees(theta - theta_a)
    bar = pressure / 1.0e5
    fig, ax = plt.subplots(figsize=(8.0, 4.5))
    ax.plot(degrees, bar, color="C3", linewidth=1.4)
    peak = int(np.argmax(bar))
    ax.annotate(f"peak {bar[peak]:.1f} bar at {degrees[peak]:.0f} deg",
                (degrees[peak], bar[peak]), xytext=(12, -4), textcoords="offset points",
                fontsize=9)
    top = 1.12 * bar.max()
    for start, stroke in zip((0, 180, 360, 540), ("intake", "compression", "expansion",
                                                  "exhaust")):
        if start:
            ax.axvline(start, color="0.6", linestyle="--", linewidth=0.8)
        ax.text(start + 90, top * 0.97, stroke, ha="center", va="top", fontsize=9, color="0.3")
    ax.set_xlim(0.0, 720.0)
    ax.set_ylim(0.0, top)
    ax.set_xticks(np.arange(0, 721, 90))
    ax.set_xlabel("crank angle in the cycle (deg; 0 = TDC at intake start, 360 = firing TDC)")
    ax.set_ylabel("in-cylinder pressure (bar)")
    cycle = int(round(theta_a / ffrf_results.ENGINE_CYCLE)) + 1
    ax.set_title(f"In-cylinder pressure, engine cycle {cycle} (t = {times[0]:.3f} .. "
                 f"{times[-1]:.3f} s), {run.label}", fontsize=10)
    ax.grid(True, linewidth=0.4)
    fig.tight_layout()
    fig.savefig(output, dpi=dpi)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="engine results files (.h5), one curve each")
    parser.add_argument("-o", "--output", required=True, help="speed chart (PNG, PDF, SVG)")
    parser.add_argument("--zoom", nargs=2, type=float, metavar=("T0", "T1"),
                        help="zoom window, s (default: the last 0.2 s or the last two engine "
                        "cycles of the first file, whichever is shorter)")
    parser.add_argument("--pressure", help="also write the pressure chart of the first file")
    parser.add_argument("--allow-incomplete", action="store_true",
                        help="also plot runs whose status is not 'complete' (killed or failed: "
                        "the steps they saved)")
    parser.add_argument("--dpi", type=int, default=150, help="resolution of raster output")
    args = parser.parse_args(argv)
    if args.zoom and not args.zoom[0] < args.zoom[1]:
        parser.error(f"--zoom {args.zoom[0]:g} {args.zoom[1]:g}: T0 must be less than T1")
    try:
        runs = ffrf_results.unique_labels([
            ffrf_results.read_engine(path, allow_incomplete=args.allow_incomplete)
            for path in args.files])
        zoom = tuple(args.zoom) if args.zoom else default_zoom(runs[0])
        plot_speed(runs, zoom, args.output, args.dpi)
        if args.pressure:
            plot_pressure(runs[0], args.pressure, args.dpi)
    except ffrf_results.ResultsError as exc:
        return ffrf_results.command_error("plot_engine.py", exc)
    written = args.output + (f" and {args.pressure}" if args.pressure else "")
    print(f"plot_engine.py: wrote {written} ({len(runs)} runs, zoom {zoom[0]:.3f} .. "
          f"{zoom[1]:.3f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
