#!/usr/bin/python3
"""Checks of the speed-against-accuracy scripts (postprocess/namelist.py, study_outputs.py,
study_chart.py, study_run.py).

  check_study.py synthetic --postprocess-dir DIR --work DIR
      on made-up data with known answers: the namelist reader against hand-parsed text and its
      round trip; rotation matrices of Euler parameters against rotations by hand; the
      crank-pin deflection of a rigid motion (zero, 1e-15) and of a pin displacement (itself);
      study_chart.py errors, Pareto front and tables on points whose errors are known, and the
      "Automatic model: predicted against observed" table of an automatic-model point whose
      errors, predictions and targets are known
  check_study.py tiny --postprocess-dir DIR --work DIR --ffrf FFRF --gmsh GMSH --input-dir DIR
      one tiny real study (tests/postprocess/study_tiny.nml: two coarse crank meshes and a
      coarse 0.3 s engine, about 10 s): every point completes, node counts grow as lc falls, the
      chart and tables are written, the crank frequency error falls with refinement, the
      errors in the tables are |x - x_ref| / |x_ref| of the CSV values; the automatic-model
      point has its columns (predicted errors finite and positive, the step, the kept modes, the
      choice) and its row in the "predicted against observed" table, beside the hand-set base
"""
import argparse
import csv
import math
import os
import subprocess
import sys

import numpy as np


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def close(what, actual, expected, rtol=0.0, atol=0.0):
    if not (abs(actual - expected) <= max(atol, rtol * abs(expected))):
        fail(f"{what} = {actual!r}, expected {expected!r} (rtol {rtol}, atol {atol})")
    print(f"ok   {what} = {actual:.6g} (expected {expected:.6g})")


def check_namelist(namelist):
    text = """! comment, with 'quotes' and / slashes
&study a = 1, b = 2.5d-3, c = 'x, y / z', d = .true. /
&family sweep = 'engine', name = 'it''s', h = 4.0e-4, 2.0e-4 ! trailing
        1.0e-4 /
"""
    groups = namelist.parse(text)
    if [g.name for g in groups] != ["study", "family"]:
        fail(f"namelist groups {[g.name for g in groups]}")
    s = groups[0]
    if (s.get("a"), s.get("b"), s.get("c"), s.get("d")) != (1, 2.5e-3, "x, y / z", True):
        fail(f"namelist values {s.items}")
    f = groups[1]
    if f.get("name") != "it's" or f.get_list("h") != [4.0e-4, 2.0e-4, 1.0e-4]:
        fail(f"namelist family {f.items}")
    again = namelist.parse(namelist.format_groups(groups))
    if [(g.name, g.items) for g in again] != [(g.name, g.items) for g in groups]:
        fail("namelist round trip changed the groups")
    for bad in ["a = 1 /", "&g a = 1", "&g 1 /", "&g a = /"]:
        try:
            namelist.parse(bad)
        except namelist.NamelistError as exc:
            print(f"ok   namelist refuses {bad!r}: {exc}")
        else:
            fail(f"namelist accepted {bad!r}")
    print("ok   namelist: values, lists, quotes, comments, round trip")


def check_outputs(study_outputs):
    # 90 deg about z: e = (cos 45, 0, 0, sin 45); A e_y = -e_x, A e_x = e_y
    c = math.cos(math.pi / 4.0)
    a = study_outputs.rotation_matrix(np.array([[c, 0.0, 0.0, c]]))[0]
    close("A(90 deg about z) e_y . (-e_x)", float(-a[0, 1]), 1.0, atol=1e-15)
    close("A(90 deg about z) e_x . e_y", float(a[1, 0]), 1.0, atol=1e-15)
    # 120 deg about (1, 1, 1)/sqrt(3) maps x -> y -> z
    e = np.array([0.5, 0.5, 0.5, 0.5])
    a = study_outputs.rotation_matrix(e)
    close("A(120 deg about (1,1,1)) e_x . e_y", float(a[1, 0]), 1.0, atol=1e-15)

    # journals at z = -/+0.0475, pin at (0, 0.045, 0); a small rigid motion u = c + w x x
    x1, x2, x3 = np.array([0, 0, -0.0475]), np.array([0, 0.045, 0.0]), np.array([0, 0, 0.0475])
    rng = np.random.default_rng(7)
    shift, w = rng.normal(size=(5, 3)) * 1e-5, rng.normal(size=(5, 3)) * 1e-4

    def motion(x):
        return np.hstack([shift + np.cross(w, x), w])

    d = study_outputs.pin_deflection(motion(x1), motion(x2), motion(x3), x1, x2, x3)
    close("pin deflection of a rigid motion (max |d|, m)", float(np.abs(d).max()), 0.0,
          atol=1e-15)
    bump = np.array([[3e-6, -2e-6, 1e-6, 0, 0, 0]])
    d = study_outputs.pin_deflection(motion(x1)[:1], motion(x2)[:1] + bump, motion(x3)[:1],
                                     x1, x2, x3)
    close("pin deflection of a pin displacement (|d|, m)", float(np.linalg.norm(d)),
          float(np.linalg.norm(bump[0, :3])), rtol=1e-12)


def synthetic_points(path):
    """Points with known errors: reference values 100 (engine outputs) and f_i = 1000 i Hz."""
    import study_run
    rows = []

    def row(id_, sweep, wall, scale, families="", roles=""):
        r = {k: "" for k in study_run.COLUMNS}
        r.update({"id": id_, "sweep": sweep, "families": families, "roles": roles,
                  "label": id_, "crank_lc": 0.006, "order": 2, "num_modes": 10,
                  "basis": "rc_normal", "rc_set": 1, "wall_s": wall, "modes_s": wall / 2,
                  "integration_s": wall / 2, "peak_mib": 100.0, "crank_nodes": 1000,
                  "status": "complete"})
        if sweep == "engine":
            r.update({"conrod_lc": 0.005, "h": 1e-4, "rho_inf": 0.8, "conrod_nodes": 500,
                      "mean_speed": 100 * (1 + scale), "amplitude": 100 * (1 - 2 * scale),
                      "peak_axial_force": 100 * (1 + 0.5 * scale),
                      "peak_pin_deflection": 100 * (1 + 0.1 * scale)})
        for i in range(1, 7):
            r[f"f{i}"] = 1000.0 * i * (1 + scale * (1 if i != 3 else 3))
        rows.append(r)

    row("e_ref", "engine", 100.0, 0.0, roles="reference")
    row("e_a", "engine", 1.0, 1e-2, families="fam1", roles="base")      # engine error 2e-2
    row("e_b", "engine", 2.0, 1e-3, families="fam1")                   # 2e-3: front
    row("e_c", "engine", 3.0, 5e-2, families="fam2")                   # dominated by e_a, e_b
    row("e_d", "engine", 10.0, 1e-4, families="fam2")                  # 2e-4: front
    row("e_chk", "engine", 50.0, 1e-5, roles="check: finer")           # 2e-5: front
    # automatic model: errors mean speed 3e-2 (target 1e-1: met), conrod force 1.5e-2 (target
    # 1e-2: not met), engine 6e-2 at 5 s: dominated by e_b, off the front
    row("e_auto", "engine", 5.0, 3e-2, families="automatic model")
    rows[-1].update({"selection": "auto", "speed_tolerance": 1e-1, "force_tolerance": 1e-2,
                     "predicted_speed": 2.5e-2, "predicted_force": 4.0e-3,
                     "predicted_step_speed": 1e-6, "predicted_step_force": 1e-3,
                     "auto_h": 2e-4, "h": 2e-4, "crank_kept_modes": 1, "conrod_kept_modes": 0,
                     "num_modes": "", "auto_model": "crank: lc 10 mm, 1 mode (1647 Hz) | "
                     "conrod: lc 8 mm, rigid (no mode) | h 0.0002 s"})
    row("c_ref", "crank", 60.0, 0.0, roles="reference")
    row("c_a", "crank", 1.0, 1e-3, families="fam1", roles="base")      # frequency error 3e-3
    row("c_b", "crank", 0.5, 1e-2, families="fam1")                    # 3e-2, cheapest: front
    with open(path, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=study_run.COLUMNS)
        writer.writeheader()
        writer.writerows(rows)


def check_chart(args, points, expect_fronts=None):
    out = os.path.splitext(points)[0]
    cmd = [sys.executable, os.path.join(args.postprocess_dir, "study_chart.py"), points,
           "--chart", out + ".png", "--markdown", out + ".md", "--front-csv",
           out + "_front.csv", "--errors-csv", out + "_errors.csv"]
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"study_chart.py exit {result.returncode}: {result.stderr}")
    for suffix in (".png", ".md", "_front.csv", "_errors.csv"):
        if not os.path.getsize(out + suffix) > 0:
            fail(f"{out + suffix} is empty")
    with open(points, newline="") as stream:
        rows = {r["id"]: r for r in csv.DictReader(stream)}
    with open(out + "_errors.csv", newline="") as stream:
        errors = {r["id"]: r for r in csv.DictReader(stream)}
    refs = {r["sweep"]: r for r in rows.values() if "reference" in r["roles"].split(";")}
    for id_, row in rows.items():
        if row["status"] != "complete":
            continue
        ref = refs[row["sweep"]]
        if row["sweep"] == "engine":
            worst = 0.0
            for key in ("mean_speed", "amplitude", "peak_axial_force", "peak_pin_deflection"):
                expected = abs(float(row[key]) - float(ref[key])) / abs(float(ref[key]))
                worst = max(worst, expected)
                close(f"{id_} error of {key}", float(errors[id_][f"error_{key}"]), expected,
                      rtol=1e-12, atol=1e-300)
            close(f"{id_} engine error (largest)", float(errors[id_]["error_engine"]), worst,
                  rtol=1e-12, atol=1e-300)
        else:
            expected = max(abs(float(row[f"f{i}"]) - float(ref[f"f{i}"])) / float(ref[f"f{i}"])
                           for i in range(1, 7))
            close(f"{id_} frequency error", float(errors[id_]["error_frequencies"]), expected,
                  rtol=1e-12, atol=1e-300)
    with open(out + "_front.csv", newline="") as stream:
        fronts = [(r["sweep"], r["id"]) for r in csv.DictReader(stream)]
    if expect_fronts is not None and fronts != expect_fronts:
        fail(f"Pareto fronts {fronts}, expected {expect_fronts}")
    with open(out + ".md") as stream:
        markdown = stream.read()
    for heading in ("Pareto front, engine", "Pareto front, crank alone", "how converged"):
        if heading not in markdown:
            fail(f"{out}.md lacks '{heading}'")
    check_auto(out, rows, markdown, errors)
    print(f"ok   study_chart.py: errors, fronts {fronts}, chart and tables")
    return rows


AUTO_COLUMNS = ["selection", "speed_tolerance", "force_tolerance", "predicted_force",
                "predicted_speed", "auto_h", "crank_kept_modes", "conrod_kept_modes",
                "auto_model"]
AUTO_HEADING = "Automatic model: predicted against observed"


def auto_table(markdown):
    """{first cell: cells} of the rows of the automatic-model table."""
    section = markdown.split(AUTO_HEADING, 1)[1].split("\n### ", 1)[0]
    table = {}
    for line in section.splitlines():
        if line.startswith("| ") and not line.startswith("| point"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            table[cells[0]] = cells
    return table


def check_auto(out, rows, markdown, errors):
    """Columns of the automatic-model points, their predictions, their table rows."""
    autos = [r for r in rows.values() if r.get("selection") == "auto"]
    if not autos:
        return
    some = next(iter(rows.values()))
    missing = [c for c in AUTO_COLUMNS if c not in some]
    if missing:
        fail(f"points CSV lacks the columns {missing}")
    if AUTO_HEADING not in markdown:
        fail(f"{out}.md lacks '{AUTO_HEADING}'")
    table = auto_table(markdown)
    for r in autos:
        if r["status"] != "complete":
            fail(f"{r['id']}: automatic-model point did not complete: {r['status']}")
        for key in ("predicted_force", "predicted_speed", "auto_h", "speed_tolerance",
                    "force_tolerance"):
            value = float(r[key])
            if not (math.isfinite(value) and value > 0.0):
                fail(f"{r['id']}: {key} = {r[key]!r}, expected finite and positive")
        for key in ("crank_kept_modes", "conrod_kept_modes"):
            if not int(r[key]) >= 0:
                fail(f"{r['id']}: {key} = {r[key]!r}")
        if not r["auto_model"] or float(r["h"]) != float(r["auto_h"]):
            fail(f"{r['id']}: auto_model {r['auto_model']!r}, h {r['h']} / auto_h "
                 f"{r['auto_h']}")
        rows_of = [cells for first, cells in table.items() if first.startswith(r["id"] + " ")]
        if len(rows_of) != 1:
            fail(f"{out}.md: {len(rows_of)} rows of {r['id']} in '{AUTO_HEADING}'")
        cells = rows_of[0]
        e = errors[r["id"]]
        for observed, predicted, target, column in (
                ("error_mean_speed", "predicted_speed", "speed_tolerance", 4),
                ("error_peak_axial_force", "predicted_force", "force_tolerance", 7)):
            close(f"{r['id']} {predicted} in the table", float(cells[column]),
                  float(r[predicted]), rtol=6e-3)
            close(f"{r['id']} observed {observed} in the table", float(cells[column + 1]),
                  float(e[observed]), rtol=6e-3, atol=1e-300)
            expected = "yes" if float(e[observed]) <= float(r[target]) else "**no**"
            if cells[column + 2] != expected:
                fail(f"{r['id']}: meets target of {observed} is {cells[column + 2]!r}, "
                     f"expected {expected!r} ({e[observed]} against {r[target]})")
            if float(e[predicted]) != float(r[predicted]):
                fail(f"{r['id']}: errors CSV {predicted} {e[predicted]} != {r[predicted]}")
    bases = [first for first in table if first.endswith("hand-set base")]
    if len(bases) != 1:
        fail(f"{out}.md: {len(bases)} hand-set base rows in '{AUTO_HEADING}'")
    print(f"ok   automatic model: {len(autos)} points, columns, predictions finite and "
          f"positive, table rows with met targets, hand-set base row")


def synthetic(args):
    sys.path.insert(0, args.postprocess_dir)
    import namelist
    import study_outputs
    check_namelist(namelist)
    check_outputs(study_outputs)
    os.makedirs(args.work, exist_ok=True)
    points = os.path.join(args.work, "synthetic_points.csv")
    synthetic_points(points)
    rows = check_chart(args, points, expect_fronts=[("engine", "e_a"), ("engine", "e_b"),
                                                    ("engine", "e_d"), ("engine", "e_chk"),
                                                    ("crank", "c_b"), ("crank", "c_a")])
    with open(os.path.join(args.work, "synthetic_points.md")) as stream:
        table = auto_table(stream.read())
    cells = table["e_auto e_auto"]
    if [cells[6], cells[9]] != ["yes", "**no**"]:
        fail(f"e_auto meets targets {[cells[6], cells[9]]}, expected ['yes', '**no**']")
    if "e_a hand-set base" not in table:
        fail(f"the hand-set base row is not e_a: {list(table)}")
    print(f"ok   automatic model table: mean speed within its target, conrod force not "
          f"({len(rows)} points)")


def tiny(args):
    os.makedirs(args.work, exist_ok=True)
    points = os.path.join(args.work, "points.csv")
    cmd = [sys.executable, os.path.join(args.postprocess_dir, "study_run.py"), args.study,
           "--ffrf", args.ffrf, "--gmsh", args.gmsh, "--input-dir", args.input_dir, "--work",
           args.work, "--csv", points]
    result = subprocess.run(cmd, capture_output=True, text=True)
    print(result.stdout)
    if result.returncode != 0:
        fail(f"study_run.py exit {result.returncode}: {result.stderr}")
    rows = check_chart(args, points)
    crank = sorted((r for r in rows.values() if r["sweep"] == "crank"),
                   key=lambda r: -float(r["crank_lc"]))
    nodes = [int(r["crank_nodes"]) for r in crank]
    if nodes != sorted(set(nodes)):
        fail(f"crank node counts {nodes} do not grow as lc falls")
    with open(os.path.join(args.work, "points_errors.csv"), newline="") as stream:
        errors = {r["id"]: r for r in csv.DictReader(stream)}
    coarse = [float(errors[r["id"]]["error_frequencies"]) for r in crank[:-1]]
    if not all(a > b for a, b in zip(coarse, coarse[1:])):
        fail(f"crank frequency errors {coarse} do not fall with refinement")
    print(f"ok   crank: nodes {nodes}, frequency errors {coarse} fall with refinement")
    engine = [r for r in rows.values() if r["sweep"] == "engine"]
    if not any(r["basis"] == "craig_bampton" for r in engine):
        fail("no Craig-Bampton engine point")
    autos = [r for r in engine if r["selection"] == "auto"]
    if not autos:
        fail("no automatic-model engine point")
    for r in engine:
        for key in ("mean_speed", "amplitude", "peak_axial_force", "peak_pin_deflection",
                    "peak_mib", "integration_s"):
            if key == "peak_pin_deflection" and r["selection"] == "auto" and \
                    int(r["crank_kept_modes"]) == 0:
                if float(r[key]) != 0.0:      # a rigid crank does not deflect
                    fail(f"{r['id']}: rigid crank, {key} = {r[key]}")
                continue
            if not float(r[key]) > 0.0:
                fail(f"{r['id']}: {key} = {r[key]}")
        if r["selection"] == "manual" and r["auto_model"]:
            fail(f"{r['id']}: a hand-set point with auto_model {r['auto_model']!r}")
    print(f"ok   engine points: every output and timing positive; automatic model: "
          + "; ".join(r["auto_model"] for r in autos))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mode", choices=["synthetic", "tiny"])
    parser.add_argument("--postprocess-dir", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--study", help="tiny: the study file")
    parser.add_argument("--ffrf", help="tiny: the ffrf program")
    parser.add_argument("--gmsh", default="gmsh", help="tiny: the gmsh program")
    parser.add_argument("--input-dir", help="tiny: folder of the base cases and .geo files")
    args = parser.parse_args()
    if args.mode == "synthetic":
        synthetic(args)
    else:
        if not (args.study and args.ffrf and args.input_dir):
            parser.error("tiny needs --study, --ffrf and --input-dir")
        tiny(args)
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
