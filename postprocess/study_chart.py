#!/usr/bin/python3
"""Chart speed against accuracy from the points of study_run.py: the error of each output against
the study's own reference over the wall time, log-log, one curve per family, the Pareto front
marked; the front as Markdown and CSV tables, with the reference, its convergence and the
machine.

Errors are relative, |x - x_ref| / |x_ref|, against the point of each sweep whose roles include
'reference' (finest mesh, most modes, smallest step):
  crank sweep:  frequencies  max over i = 1..n of |f_i - f_i,ref| / f_i,ref (n = &study
                num_frequencies, default 6)
  engine sweep: mean_speed, amplitude (speed oscillation), peak_axial_force (conrod),
                peak_pin_deflection (crank pin), and engine = the largest of these four
A point is on the Pareto front of an error when no point of the same sweep is both cheaper
(wall time) and at least as accurate. The 'check' points (the reference with one parameter
one level coarser) say how converged the reference is: their differences to it are tabled.

Automatic-model points (selection = 'auto', study_run.py's &auto) are charted as their own
family (stars, no line), with their predicted errors of the mean speed and the conrod force
(hollow stars joined to the observed ones); the Markdown's "Automatic model: predicted against
observed" table gives per point the targets, the model chosen, the wall time, the predicted and
observed errors of the mean speed and the peak conrod force and whether each observed error
meets its target, with the hand-set engine base point (&base) for comparison.

    study_chart.py points.csv --chart speed_accuracy.png --markdown speed_accuracy.md \\
        --front-csv speed_accuracy_front.csv
"""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

ENGINE_OUTPUTS = [("mean_speed", "mean speed"), ("amplitude", "speed oscillation"),
                  ("peak_axial_force", "conrod force"), ("peak_pin_deflection", "pin deflection")]
# (sweep, error key, panel title)
PANELS = [("crank", "frequencies", "crank alone: frequencies f1..f{n}"),
          ("engine", "mean_speed", "engine: regime mean speed"),
          ("engine", "amplitude", "engine: speed oscillation (max-min)/2"),
          ("engine", "peak_axial_force", "engine: peak conrod axial force"),
          ("engine", "peak_pin_deflection", "engine: peak crank-pin deflection"),
          ("engine", "engine", "engine: largest of the four errors")]
MARKERS = "osD^v<>ph*X"
NUMERIC = ["crank_lc", "conrod_lc", "h", "rho_inf", "wall_s", "modes_s", "integration_s",
           "output_s", "ffrf_total_s", "peak_mib", "peak_stage_mib", "mean_speed", "amplitude",
           "peak_axial_force", "peak_pin_deflection"] + [f"f{i}" for i in range(1, 13)] + [
           "speed_tolerance", "force_tolerance", "predicted_force", "predicted_speed",
           "predicted_step_force", "predicted_step_speed", "auto_h"]
INTEGER = ["order", "num_modes", "rc_set", "crank_nodes", "conrod_nodes", "num_coordinates",
           "crank_kept_modes", "conrod_kept_modes"]
# automatic-model points: their family in the chart and what each prediction is compared with
AUTO_FAMILY = "automatic model"
AUTO_STYLE = ("#c0143c", "*")
PREDICTED = {"mean_speed": ("predicted_speed", "speed_tolerance"),
             "peak_axial_force": ("predicted_force", "force_tolerance")}


class StudyDataError(Exception):
    """Points that cannot be charted (no reference, failed reference, ...)."""


def read_points(path):
    """Rows of the points CSV with numbers converted (None when empty) and lists split."""
    with open(path, newline="") as stream:
        rows = list(csv.DictReader(stream))
    for row in rows:
        for key in NUMERIC:
            row[key] = float(row[key]) if row.get(key) not in (None, "") else None
        for key in INTEGER:
            row[key] = int(float(row[key])) if row.get(key) not in (None, "") else None
        row["families"] = [f for f in row.get("families", "").split(";") if f]
        row["roles"] = [r for r in row.get("roles", "").split(";") if r]
        row["selection"] = row.get("selection") or ""
        row["auto_model"] = row.get("auto_model") or ""
    return rows


def is_auto(row):
    """An automatic-model point (ffrf chose mesh, modes and step)."""
    return row.get("selection") == "auto"


def auto_model(row):
    """The automatic model's choice as text without '|' (Markdown table cells)."""
    return row["auto_model"].replace(" | ", "; ").replace("|", "/")


def targets(row):
    """'speed 1e-03, force 1e-02' of an automatic-model point."""
    return f"speed {row['speed_tolerance']:.0e}, force {row['force_tolerance']:.0e}"


def configuration(row):
    """'Tet10 lc 6/5 mm, 10 modes RC normal (RC set 1), h 1e-04 s, rho_inf 0.8'; for an
    automatic-model point its targets and choice."""
    element = "Tet4" if row["order"] == 1 else "Tet10"
    if is_auto(row):
        return (f"automatic model ({targets(row)}): {element}, {auto_model(row)}, "
                f"rho_inf {row['rho_inf']:g}")
    sizes = f"{row['crank_lc'] * 1000:g}"
    if row.get("conrod_lc"):
        sizes += f"/{row['conrod_lc'] * 1000:.3g}"
    if row["basis"] == "craig_bampton":
        basis = f"CB static + {row['num_modes']} fixed-interface modes"
    else:
        basis = f"{row['num_modes']} RC normal modes"
    text = f"{element} lc {sizes} mm, {basis}, RC set {row['rc_set']}"
    if row["sweep"] == "engine":
        text += f", h {row['h']:.3g} s, rho_inf {row['rho_inf']:g}"
    return text


def relative_error(value, reference):
    """|value - reference| / |reference|; inf when the reference is 0 and the value is not."""
    if reference == 0.0:
        return 0.0 if value == 0.0 else math.inf
    return abs(value - reference) / abs(reference)


def compute_errors(rows, num_frequencies):
    """Add row['errors'] = {key: relative error} to every complete row; returns {sweep:
    reference row}. StudyDataError if a sweep has no complete reference."""
    references = {}
    for sweep in ("crank", "engine"):
        members = [r for r in rows if r["sweep"] == sweep]
        if not members:
            continue
        refs = [r for r in members if "reference" in r["roles"]]
        if len(refs) != 1:
            raise StudyDataError(f"sweep {sweep}: {len(refs)} reference points, expected one")
        ref = refs[0]
        if ref["status"] != "complete":
            raise StudyDataError(f"sweep {sweep}: the reference {ref['id']} did not complete "
                                 f"({ref['status']})")
        references[sweep] = ref
        for row in members:
            if row["status"] != "complete":
                continue
            errors = {}
            if sweep == "crank":
                pairs = [(row[f"f{i}"], ref[f"f{i}"]) for i in range(1, num_frequencies + 1)]
                if any(a is None or b is None for a, b in pairs):
                    raise StudyDataError(f"{row['id']}: fewer than {num_frequencies} "
                                         f"frequencies (num_modes too small?)")
                errors["frequencies"] = max(relative_error(a, b) for a, b in pairs)
            else:
                for key, _ in ENGINE_OUTPUTS:
                    errors[key] = relative_error(row[key], ref[key])
                errors["engine"] = max(errors[key] for key, _ in ENGINE_OUTPUTS)
            row["errors"] = errors
    return references


def pareto_front(points, key):
    """The points (rows with errors) on the front of error `key` against wall time, cheapest
    first: each is more accurate than every cheaper point."""
    front = []
    best = math.inf
    for row in sorted(points, key=lambda r: (r["wall_s"], r["errors"][key])):
        if row["errors"][key] < best:
            front.append(row)
            best = row["errors"][key]
    return front


def charted(rows, sweep):
    """Complete points of a sweep other than its reference."""
    return [r for r in rows if r["sweep"] == sweep and r["status"] == "complete"
            and "reference" not in r["roles"]]


def draw(rows, path, num_frequencies, title):
    families = []
    for row in rows:
        for family in row["families"]:
            if family not in families:
                families.append(family)
    colors = [c for c in plt.get_cmap("tab10").colors if c != plt.get_cmap("tab10")(7)[:3]]
    colors += list(plt.get_cmap("Dark2").colors)
    style = {f: (colors[i % len(colors)], MARKERS[i % len(MARKERS)])
             for i, f in enumerate(f for f in families if f != AUTO_FAMILY)}
    style[AUTO_FAMILY] = AUTO_STYLE
    fig, axes = plt.subplots(2, 3, figsize=(15.0, 9.5))
    handles = {}
    for ax, (sweep, key, panel) in zip(axes.flat, PANELS):
        points = charted(rows, sweep)
        ax.set_title(panel.format(n=num_frequencies), fontsize=10)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time of the ffrf run (s)")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.LogFormatter(labelOnlyBase=False,
                                                                    minor_thresholds=(2, 0.5)))
        ax.set_ylabel("relative error")
        ax.grid(True, which="both", alpha=0.25)
        if not points:
            ax.text(0.5, 0.5, "no points", transform=ax.transAxes, ha="center")
            continue
        floor = 1e-12
        for family in families:
            members = sorted((r for r in points if family in r["families"]),
                             key=lambda r: r["wall_s"])
            if not members:
                continue
            color, marker = style[family]
            if family == AUTO_FAMILY:
                continue
            line, = ax.plot([r["wall_s"] for r in members],
                            [max(r["errors"][key], floor) for r in members], marker=marker,
                            color=color, label=family, markersize=5, linewidth=1.2)
            handles[family] = line
        autos = sorted((r for r in points if is_auto(r)), key=lambda r: r["wall_s"])
        if autos:
            color, marker = AUTO_STYLE
            xs = [r["wall_s"] for r in autos]
            observed = [max(r["errors"][key], floor) for r in autos]
            if key in PREDICTED:
                predicted = [max(r[PREDICTED[key][0]], floor)
                             if r.get(PREDICTED[key][0]) is not None else None for r in autos]
                for x, yo, yp in zip(xs, observed, predicted):
                    if yp is not None:
                        ax.plot([x, x], [yo, yp], color=color, linewidth=0.8, linestyle=":")
                pairs = [(x, y) for x, y in zip(xs, predicted) if y is not None]
                if pairs:
                    line, = ax.plot([x for x, _ in pairs], [y for _, y in pairs], marker,
                                    markerfacecolor="none", markeredgecolor=color,
                                    markersize=11, linestyle="none",
                                    label=f"{AUTO_FAMILY}: predicted")
                    handles[f"{AUTO_FAMILY}: predicted"] = line
            line, = ax.plot(xs, observed, marker, color=color, markersize=12, linestyle="none",
                            markeredgecolor="k", markeredgewidth=0.5,
                            label=f"{AUTO_FAMILY} (targets speed/force)")
            handles[f"{AUTO_FAMILY} (targets speed/force)"] = line
            if key in PREDICTED:            # targets by the points, staggered downwards
                for i, (r, x, y) in enumerate(zip(autos, xs, observed)):
                    ax.annotate(f"{r['speed_tolerance']:.0e}/{r['force_tolerance']:.0e}",
                                (x, y), textcoords="offset points", xytext=(7, -10 - 9 * i),
                                fontsize=7, color=color)
        checks = [r for r in points if any(x.startswith("check") for x in r["roles"])]
        if checks:
            line, = ax.plot([r["wall_s"] for r in checks],
                            [max(r["errors"][key], floor) for r in checks], "x",
                            color="k", markersize=7, label="reference, one level coarser")
            handles["reference, one level coarser"] = line
        front = pareto_front(points, key)
        xs = [r["wall_s"] for r in front]
        ys = [max(r["errors"][key], floor) for r in front]
        line, = ax.plot(xs, ys, drawstyle="steps-post", color="k", linestyle="--",
                        linewidth=0.9, label="Pareto front")
        ax.plot(xs, ys, "o", markerfacecolor="none", markeredgecolor="k", markersize=10,
                markeredgewidth=1.2)
        handles["Pareto front"] = line
    fig.legend(list(handles.values()), list(handles.keys()), loc="lower center",
               ncol=min(len(handles), 5), fontsize=9, frameon=False)
    fig.suptitle(title, fontsize=11)
    fig.tight_layout(rect=(0, 0.07, 1, 0.96))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def tags(row):
    """'modes per body, base': the families and roles of a point."""
    return ", ".join(row["families"] + [r for r in row["roles"] if r != "reference"])


def fmt(value, digits=2):
    return "n/a" if value is None else f"{value:.{digits}e}"


def seconds(value):
    return "n/a" if value is None else f"{value:.1f}"


def write_front_csv(path, rows):
    columns = ["sweep", "metric", "id", "configuration", "families", "wall_s", "modes_s",
               "integration_s", "peak_mib", "error_frequencies", "error_mean_speed",
               "error_amplitude", "error_peak_axial_force", "error_peak_pin_deflection",
               "error_engine"]
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(columns)
        for sweep, key in (("engine", "engine"), ("crank", "frequencies")):
            for row in pareto_front(charted(rows, sweep), key):
                e = row["errors"]
                writer.writerow([sweep, key, row["id"], configuration(row),
                                 ";".join(row["families"] + [x for x in row["roles"]
                                                             if x != "reference"]),
                                 repr(row["wall_s"]), repr(row["modes_s"]),
                                 repr(row["integration_s"]), repr(row["peak_mib"])]
                                + [repr(e[k]) if k in e else "" for k in
                                   ("frequencies", "mean_speed", "amplitude", "peak_axial_force",
                                    "peak_pin_deflection", "engine")])


def write_markdown(stream, rows, references, meta, num_frequencies):
    machine = meta.get("machine", {})
    stream.write("### Pareto front, engine (largest relative error of mean speed, speed "
                 "oscillation, peak conrod axial force, peak crank-pin deflection)\n\n")
    stream.write("| configuration | family | wall (s) | modes (s) | integration (s) | peak "
                 "memory (MiB) | mean speed | oscillation | conrod force | pin deflection |\n")
    stream.write("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n")
    for row in pareto_front(charted(rows, "engine"), "engine"):
        e = row["errors"]
        stream.write(f"| {configuration(row)} | {tags(row)} "
                     f"| {seconds(row['wall_s'])} | {seconds(row['modes_s'])} "
                     f"| {seconds(row['integration_s'])} | {row['peak_mib']:.0f} | "
                     + " | ".join(fmt(e[k]) for k, _ in ENGINE_OUTPUTS) + " |\n")
    stream.write(f"\n### Pareto front, crank alone (largest relative error of "
                 f"f1..f{num_frequencies})\n\n")
    stream.write("| configuration | family | wall (s) | peak memory (MiB) | error |\n")
    stream.write("|---|---|---:|---:|---:|\n")
    for row in pareto_front(charted(rows, "crank"), "frequencies"):
        stream.write(f"| {configuration(row)} | {tags(row)} "
                     f"| {seconds(row['wall_s'])} | {row['peak_mib']:.0f} "
                     f"| {fmt(row['errors']['frequencies'])} |\n")

    stream.write("\n### The reference and how converged it is\n\n")
    for sweep, ref in references.items():
        if sweep == "engine":
            values = (f"mean speed {ref['mean_speed']:.4f} rad/s, oscillation "
                      f"{ref['amplitude']:.4f} rad/s, peak conrod axial force "
                      f"{ref['peak_axial_force']:.1f} N, peak crank-pin deflection "
                      f"{ref['peak_pin_deflection'] * 1e6:.4f} um")
        else:
            values = ", ".join(f"{ref[f'f{i}']:.2f}" for i in range(1, num_frequencies + 1))
            values = f"f1..f{num_frequencies} = {values} Hz"
        stream.write(f"- {sweep} reference ({ref['id']}): {configuration(ref)}; "
                     f"{ref['crank_nodes']} crank nodes"
                     + (f", {ref['conrod_nodes']} conrod nodes" if ref.get("conrod_nodes")
                        else "")
                     + f"; wall {seconds(ref['wall_s'])} s, peak {ref['peak_mib']:.0f} MiB; "
                     f"{values}\n")
    stream.write("\nRelative change of each output when one parameter of the reference goes one "
                 "level coarser (an estimate of the reference's own error):\n\n")
    stream.write("| sweep | change | " + " | ".join(name for _, name in ENGINE_OUTPUTS)
                 + f" | f1..f{num_frequencies} |\n")
    stream.write("|---|---|" + "---:|" * (len(ENGINE_OUTPUTS) + 1) + "\n")
    for row in rows:
        checks = [x[len("check: "):] for x in row["roles"] if x.startswith("check: ")]
        if not checks or row["status"] != "complete":
            continue
        e = row["errors"]
        cells = [fmt(e.get(k)) if row["sweep"] == "engine" else "" for k, _ in ENGINE_OUTPUTS]
        cells.append(fmt(e.get("frequencies")) if row["sweep"] == "crank" else "")
        stream.write(f"| {row['sweep']} | {', '.join(checks)} ({configuration(row)}) | "
                     + " | ".join(cells) + " |\n")

    write_auto_section(stream, rows, references)

    complete = [r for r in rows if r["status"] == "complete"]
    failed = [r for r in rows if r["status"] != "complete"]
    stream.write(f"\n{len(rows)} points ({sum(r['sweep'] == 'engine' for r in rows)} engine, "
                 f"{sum(r['sweep'] == 'crank' for r in rows)} crank alone), "
                 f"{len(complete)} complete")
    if failed:
        stream.write(" (failed: " + ", ".join(f"{r['id']} {r['status']}" for r in failed) + ")")
    if "total_wall_s" in meta:
        stream.write(f"; whole study {meta['total_wall_s'] / 60.0:.1f} min (meshing "
                     f"{meta.get('mesh_wall_s', 0.0):.0f} s)")
    if machine:
        stream.write(f"; machine: {machine.get('cores')} cores ({machine.get('cpu', '?')}), "
                     f"{machine.get('memory_gib', '?')} GiB, {meta.get('date', '')}")
    stream.write(".\n")


def meets(observed, target):
    return "n/a" if observed is None or target is None else (
        "yes" if observed <= target else "**no**")


def write_auto_section(stream, rows, references):
    """The 'Automatic model: predicted against observed' table (nothing without auto points)."""
    autos = [r for r in rows if r["sweep"] == "engine" and is_auto(r)]
    if not autos:
        return
    ref = references.get("engine")
    stream.write("\n### Automatic model: predicted against observed\n\n")
    stream.write("ffrf's automatic model (`&model selection = 'auto'`) chooses each flexible "
                 "body's mesh among the candidates, the modes it keeps and the time step so that "
                 "its predicted relative errors of the regime mean speed and of the peak joint "
                 "(conrod) force meet the targets. Observed: the relative error against the "
                 "engine reference"
                 + (f" ({ref['id']})" if ref else "")
                 + ", as for every point. The engine's hand-set base point (&base: mesh, modes "
                 "and step given) is the last row, for comparison. The speed oscillation and the "
                 "crank-pin deflection are not targeted.\n\n")
    stream.write("| point | targets (speed, force) | model | wall (s) | mean speed: predicted "
                 "| observed | meets target | conrod force: predicted | observed | meets target "
                 "| oscillation, pin deflection (observed) |\n")
    stream.write("|---|---|---|---:|---:|---:|---|---:|---:|---|---:|\n")
    for row in autos:
        if row["status"] != "complete":
            stream.write(f"| {row['id']} {row['label']} | {targets(row)} | failed: "
                         f"{row['status']} | | | | | | | | |\n")
            continue
        e = row["errors"]
        element = "Tet4" if row["order"] == 1 else "Tet10"
        stream.write(f"| {row['id']} {row['label']} | {row['speed_tolerance']:.0e}, "
                     f"{row['force_tolerance']:.0e} | {element}, {auto_model(row)} "
                     f"| {seconds(row['wall_s'])} "
                     f"| {fmt(row['predicted_speed'])} | {fmt(e['mean_speed'])} "
                     f"| {meets(e['mean_speed'], row['speed_tolerance'])} "
                     f"| {fmt(row['predicted_force'])} | {fmt(e['peak_axial_force'])} "
                     f"| {meets(e['peak_axial_force'], row['force_tolerance'])} "
                     f"| {fmt(e['amplitude'])}, {fmt(e['peak_pin_deflection'])} |\n")
    for row in rows:
        if row["sweep"] != "engine" or "base" not in row["roles"] or \
                row["status"] != "complete":
            continue
        e = row["errors"]
        stream.write(f"| {row['id']} hand-set base | none | {configuration(row)} "
                     f"| {seconds(row['wall_s'])} | n/a | {fmt(e['mean_speed'])} | n/a | n/a "
                     f"| {fmt(e['peak_axial_force'])} | n/a "
                     f"| {fmt(e['amplitude'])}, {fmt(e['peak_pin_deflection'])} |\n")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("points", help="points CSV of study_run.py (its .json beside it, if "
                        "present, gives the machine and the study's wall time)")
    parser.add_argument("--chart", help="write the chart (PNG) here")
    parser.add_argument("--markdown", help="write the front, reference and convergence tables "
                        "(Markdown) here")
    parser.add_argument("--front-csv", help="write the Pareto fronts (CSV) here")
    parser.add_argument("--errors-csv", help="write every point with its errors (CSV) here")
    parser.add_argument("--frequencies", type=int, default=None,
                        help="frequencies compared (default: the study's num_frequencies, 6)")
    args = parser.parse_args(argv)
    meta_path = os.path.splitext(args.points)[0] + ".json"
    meta = {}
    if os.path.exists(meta_path):
        with open(meta_path) as stream:
            meta = json.load(stream)
    num_frequencies = args.frequencies or meta.get("settings", {}).get("num_frequencies", 6)
    try:
        rows = read_points(args.points)
        references = compute_errors(rows, num_frequencies)
    except (OSError, KeyError, ValueError, StudyDataError) as exc:
        print(f"study_chart.py: error: {args.points}: {exc}", file=sys.stderr)
        return 2
    machine = meta.get("machine", {})
    title = ("Error against wall time (OPENBLAS_NUM_THREADS=1)"
             + (f", {machine.get('cores')} cores, {machine.get('memory_gib')} GiB, "
                f"{machine.get('cpu', '')}" if machine else ""))
    if args.chart:
        draw(rows, args.chart, num_frequencies, title)
    if args.markdown:
        with open(args.markdown, "w") as stream:
            write_markdown(stream, rows, references, meta, num_frequencies)
    if args.front_csv:
        write_front_csv(args.front_csv, rows)
    if args.errors_csv:
        keys = ["frequencies"] + [k for k, _ in ENGINE_OUTPUTS] + ["engine"]
        with open(args.errors_csv, "w", newline="") as stream:
            writer = csv.writer(stream)
            predictions = ["predicted_speed", "predicted_force"]
            writer.writerow(["id", "sweep", "configuration", "families", "roles", "wall_s",
                             "peak_mib", "status"] + [f"error_{k}" for k in keys]
                            + ["selection"] + predictions)
            for row in rows:
                e = row.get("errors", {})
                writer.writerow([row["id"], row["sweep"], configuration(row),
                                 ";".join(row["families"]), ";".join(row["roles"]),
                                 repr(row["wall_s"]), repr(row["peak_mib"]), row["status"]]
                                + [repr(e[k]) if k in e else "" for k in keys]
                                + [row["selection"]]
                                + [repr(row[k]) if row.get(k) is not None else ""
                                   for k in predictions])
    if not (args.chart or args.markdown or args.front_csv or args.errors_csv):
        write_markdown(sys.stdout, rows, references, meta, num_frequencies)
    return 0


if __name__ == "__main__":
    sys.exit(main())
