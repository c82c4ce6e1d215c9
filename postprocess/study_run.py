#!/usr/bin/python3
"""Run the speed-against-accuracy sweep of a study file (input/study.nml) and record one CSV row
per point: its parameters, mesh sizes, wall time and peak memory per stage, and the outputs that
matter (crank frequencies; regime mean speed, speed oscillation, peak conrod axial force, peak
crank-pin deflection: study_outputs.py). study_chart.py turns the CSV into errors against the
study's own reference, the chart and the Pareto-front table.

The study file is a Fortran-style namelist (namelist.py reads it); see input/study.nml:
  &study      base cases, geometry, regime cycles, which joint and interfaces the outputs use,
              modal_damping (damping ratio of every mode of the crank and the conrod in the
              engine cases; default 0 as in scene.md)
  &base       sweep = 'engine' | 'crank' and the parameters of the base point of that sweep
  &reference  sweep and the parameters that differ from the base: the converged reference
  &check      sweep, name and parameters that differ from the reference (one level coarser in
              one parameter): how converged the reference is
  &family     sweep, name and lists of parameter values (equal lengths, or one value for all):
              one point per position, the other parameters from the base
  &auto       sweep = 'engine', name, speed_tolerance, force_tolerance: one point with ffrf's
              automatic model (&model selection = 'auto') for these targets (relative error of
              the regime mean speed and of the joint forces): ffrf picks each body's mesh among
              the candidates of &study auto_crank_lc, auto_conrod_lc (m; the finest is the
              body's mesh_file, the others its coarse_meshes, coarse to fine; order, rc_set and
              rho_inf of the engine &base, RC normal candidate modes), the modes it keeps and the
              time step; the point records what it chose and its predicted errors
              (study_outputs.model_selection), study_chart.py sets them against the errors
              observed against the reference. Every other engine point gives num_modes and h,
              and runs with &model selection = 'manual'
  &position   body, interface, xyz: a virtual node put at this point (m, body frame) in every
              case, instead of the area centroid of the face, which moves with the mesh (by up
              to 0.25 um on a 10 mm crank mesh: enough to leave the over-constrained engine's
              starting pose inconsistent at the 1e-9 level, where its assembly stalls)
Parameters: crank_lc, conrod_lc (m; conrod_lc follows crank_lc in proportion to the base when
not given), order (1 Tet4, 2 Tet10), num_modes (per flexible body; fixed-interface modes for
Craig-Bampton), basis ('rc_normal' or 'craig_bampton'), rc_set (1, 2, 3: the crank's &interface
groups of the &study rc_cases), h (s), rho_inf; the crank sweep (modal runs of the crank alone)
uses crank_lc, order, num_modes, basis, rc_set.

Per point: the mesh of each body size and order (gmsh -setnumber lc/order, cached under
WORK/meshes; the node count must change with lc, else gmsh ignored the size), a case file
written from the base case (WORK/<sweep>/<id>.nml), one ffrf run (OPENBLAS_NUM_THREADS=1) timed
by the wall clock with the peak resident memory of the process (wait4's ru_maxrss), and the
stage times of its results file. Identical points of several families run once. An &auto point
meshes all its candidates and runs as the others; its row adds the choice (selection = 'auto',
the targets, predicted_force, predicted_speed and their time-step parts, auto_h, the kept modes
per body, auto_model: a short text of the choice) and takes crank_lc, conrod_lc, the node counts
and h of the mesh and step chosen (num_modes empty: per body in crank/conrod_kept_modes).

    study_run.py input/study.nml --ffrf build/release/driver/ffrf --work build/release/study \\
        --csv build/release/study/points.csv
"""
import argparse
import csv
import datetime
import json
import os
import platform
import re
import subprocess
import sys
import time

import namelist
import study_outputs
import ffrf_results

PARAMETERS = ["crank_lc", "conrod_lc", "order", "num_modes", "basis", "rc_set", "h", "rho_inf"]
CRANK_PARAMETERS = ["crank_lc", "order", "num_modes", "basis", "rc_set"]
SWEEPS = ["crank", "engine"]
NUM_FREQUENCIES_MAX = 12

AUTO_FAMILY = "automatic model"
# the automatic model's choice and predictions (empty for the other points; selection is
# 'manual' for every other engine point)
AUTO_COLUMNS = ["selection", "speed_tolerance", "force_tolerance", "predicted_force",
                "predicted_speed", "predicted_step_force", "predicted_step_speed", "auto_h",
                "crank_kept_modes", "conrod_kept_modes", "auto_model"]
# CSV columns (study_chart.py reads them by name)
COLUMNS = (["id", "sweep", "families", "roles", "label"] + PARAMETERS
           + ["crank_nodes", "conrod_nodes", "num_coordinates", "wall_s", "modes_s",
              "integration_s", "output_s", "ffrf_total_s", "peak_mib", "peak_stage_mib",
              "mean_speed", "amplitude", "peak_axial_force", "peak_pin_deflection"]
           + [f"f{i}" for i in range(1, NUM_FREQUENCIES_MAX + 1)]
           + AUTO_COLUMNS
           + ["status", "case", "results"])


class StudyError(Exception):
    """A study file or run that cannot be used (the message says what and where)."""


def number(value, what):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise StudyError(f"{what} = {value!r}: must be a number")
    return value


def check_parameters(params, sweep, where):
    allowed = CRANK_PARAMETERS if sweep == "crank" else PARAMETERS
    for key, value in params.items():
        if key not in allowed:
            raise StudyError(f"{where}: parameter {key} is not one of the {sweep} sweep's "
                             f"({', '.join(allowed)})")
        if key in ("crank_lc", "conrod_lc", "h") and not number(value, f"{where}: {key}") > 0:
            raise StudyError(f"{where}: {key} = {value} must be positive")
        if key == "order" and value not in (1, 2):
            raise StudyError(f"{where}: order = {value!r}, must be 1 (Tet4) or 2 (Tet10)")
        if key == "num_modes" and not (isinstance(value, int) and value >= 1):
            raise StudyError(f"{where}: num_modes = {value!r}, must be a positive integer")
        if key == "basis" and value not in ("rc_normal", "craig_bampton"):
            raise StudyError(f"{where}: basis = {value!r}, must be 'rc_normal' or "
                             f"'craig_bampton'")
        if key == "rho_inf" and not 0.0 <= number(value, f"{where}: rho_inf") < 1.0:
            raise StudyError(f"{where}: rho_inf = {value}, must lie in [0, 1)")


class Study:
    """The parsed study file: settings, per-sweep base/reference/checks, families."""

    def __init__(self, path):
        try:
            groups = namelist.read(path)
        except (OSError, namelist.NamelistError) as exc:
            raise StudyError(f"{path}: {exc}") from exc
        known = {"study", "base", "reference", "check", "family", "auto", "position"}
        for group in groups:
            if group.name not in known:
                raise StudyError(f"{path}: unknown group &{group.name} (groups: "
                                 f"{', '.join(sorted(known))})")
        settings = namelist.find_all(groups, "study")
        if len(settings) != 1:
            raise StudyError(f"{path}: {len(settings)} &study groups, expected one")
        self.settings = self._settings(settings[0], path)
        self.base, self.reference, self.checks, self.families = {}, {}, {}, {}
        self.autos = []                     # (name, {speed_tolerance, force_tolerance})
        for sweep in SWEEPS:
            self.checks[sweep] = []
            self.families[sweep] = []
        self.positions = []
        for group in namelist.find_all(groups, "position"):
            xyz = group.get_list("xyz", [])
            if not (group.get("body") and group.get("interface") and len(xyz) == 3):
                raise StudyError(f"{path}, &position: needs body, interface and xyz = x, y, z "
                                 f"(got {group.items})")
            self.positions.append((group.get("body"), group.get("interface"),
                                   [float(v) for v in xyz]))
        for group in groups:
            if group.name in ("study", "position"):
                continue
            sweep = group.get("sweep")
            where = f"{path}, &{group.name}" + (f" '{group.get('name')}'"
                                                 if group.get("name") else "")
            if sweep not in SWEEPS:
                raise StudyError(f"{where}: sweep = {sweep!r}, must be 'engine' or 'crank'")
            params = {k: group.get(k) for k in group.keys() if k not in ("sweep", "name")}
            if group.name == "family":
                self._add_family(sweep, group.get("name"), group, where)
                continue
            if group.name == "auto":
                self._add_auto(sweep, group, where)
                continue
            check_parameters(params, sweep, where)
            if group.name == "base":
                self.base[sweep] = params
            elif group.name == "reference":
                self.reference[sweep] = params
            else:
                self.checks[sweep].append((group.get("name") or ", ".join(params), params))
        for sweep in SWEEPS:
            if sweep in self.base:
                missing = [k for k in (CRANK_PARAMETERS if sweep == "crank" else PARAMETERS)
                           if k not in self.base[sweep]]
                if missing:
                    raise StudyError(f"{path}: &base sweep = '{sweep}' lacks "
                                     f"{', '.join(missing)}")
                if sweep not in self.reference:
                    raise StudyError(f"{path}: no &reference for sweep = '{sweep}'")
            elif self.reference.get(sweep) or self.checks[sweep] or self.families[sweep] or \
                    (sweep == "engine" and self.autos):
                raise StudyError(f"{path}: groups for sweep = '{sweep}' but no &base for it")
        if self.autos:
            for key in ("auto_crank_lc", "auto_conrod_lc"):
                sizes = self.settings[key]
                if not 1 <= len(sizes) <= 5:
                    raise StudyError(f"{path}, &study: {key} = {sizes}: the &auto points need "
                                     f"1 to 5 candidate sizes (ffrf takes up to 4 coarse_meshes "
                                     f"and the mesh_file)")
                for value in sizes:
                    if not number(value, f"{path}, &study: {key}") > 0:
                        raise StudyError(f"{path}, &study: {key} = {sizes}: sizes must be "
                                         f"positive")
                if len({round(v * 1.0e6) for v in sizes}) != len(sizes):
                    raise StudyError(f"{path}, &study: {key} = {sizes}: two sizes give the same "
                                     f"mesh (sizes are named in um)")

    @staticmethod
    def _settings(group, path):
        defaults = {"engine_case": "engine_rc1.nml", "crank_case": "crank_rc1.nml",
                    "rc_cases": ["crank_rc1.nml", "crank_rc2.nml", "crank_rc3.nml"],
                    "crank_geo": "crank.geo", "conrod_geo": "conrod.geo", "t_end": 2.0,
                    "cycles": 2, "force_joint": "piston_pin", "force_side": 1,
                    "force_body": "conrod", "crank_body": "crank", "conrod_body": "conrod",
                    "pin_interface": "B2", "journal_interfaces": ["B1", "B3"],
                    "num_frequencies": 6, "modal_damping": 0.0, "auto_crank_lc": [],
                    "auto_conrod_lc": []}
        settings = dict(defaults)
        for key in group.keys():
            if key not in defaults:
                raise StudyError(f"{path}, &study: unknown key {key} (keys: "
                                 f"{', '.join(defaults)})")
            value = group.get_list(key) if isinstance(defaults[key], list) else group.get(key)
            settings[key] = value
        if len(settings["journal_interfaces"]) != 2:
            raise StudyError(f"{path}, &study: journal_interfaces needs two names")
        if not 0.0 <= number(settings["modal_damping"], "&study modal_damping") < 1.0:
            raise StudyError(f"{path}, &study: modal_damping = {settings['modal_damping']}, "
                             f"must lie in [0, 1)")
        if not 1 <= settings["num_frequencies"] <= NUM_FREQUENCIES_MAX:
            raise StudyError(f"{path}, &study: num_frequencies must lie in 1.."
                             f"{NUM_FREQUENCIES_MAX}")
        return settings

    def _add_family(self, sweep, name, group, where):
        if not name:
            raise StudyError(f"{where}: a &family needs a name")
        lists = {k: group.get_list(k) for k in group.keys() if k not in ("sweep", "name")}
        if not lists:
            raise StudyError(f"{where}: no parameter varies")
        length = max(len(v) for v in lists.values())
        for key, values in lists.items():
            if len(values) not in (1, length):
                raise StudyError(f"{where}: {key} has {len(values)} values, the longest list "
                                 f"has {length}: give one value or {length}")
        points = []
        for i in range(length):
            params = {k: (v[i] if len(v) > 1 else v[0]) for k, v in lists.items()}
            check_parameters(params, sweep, where)
            points.append(params)
        varied = [k for k, v in lists.items() if len(v) > 1] or list(lists)
        self.families[sweep].append((name, points, varied))

    def _add_auto(self, sweep, group, where):
        if sweep != "engine":
            raise StudyError(f"{where}: the automatic model is for the engine sweep only")
        if not group.get("name"):
            raise StudyError(f"{where}: an &auto needs a name")
        targets = {}
        for key in group.keys():
            if key in ("sweep", "name"):
                continue
            if key not in ("speed_tolerance", "force_tolerance"):
                raise StudyError(f"{where}: unknown key {key} (keys: sweep, name, "
                                 f"speed_tolerance, force_tolerance)")
            value = group.get(key)
            if not (number(value, f"{where}: {key}") > 0 and value < 1):
                raise StudyError(f"{where}: {key} = {value}, must lie in (0, 1)")
            targets[key] = float(value)
        missing = [k for k in ("speed_tolerance", "force_tolerance") if k not in targets]
        if missing:
            raise StudyError(f"{where}: lacks {', '.join(missing)}")
        self.autos.append((group.get("name"), targets))

    def auto_candidates(self):
        """Candidate sizes of the automatic model, coarse to fine: (crank lcs, conrod lcs)."""
        return (sorted(self.settings["auto_crank_lc"], reverse=True),
                sorted(self.settings["auto_conrod_lc"], reverse=True))

    def resolve(self, sweep, overrides, base=None):
        """Full parameters of a point: the base (or `base`) with `overrides`; conrod_lc follows
        crank_lc in proportion when the overrides change crank_lc only."""
        start = dict(self.base[sweep] if base is None else base)
        params = dict(start)
        params.update(overrides)
        if sweep == "engine" and "crank_lc" in overrides and "conrod_lc" not in overrides:
            params["conrod_lc"] = start["conrod_lc"] * overrides["crank_lc"] / start["crank_lc"]
        return params


def point_key(sweep, params):
    return (sweep,) + tuple((k, round(v, 12) if isinstance(v, float) else v)
                            for k, v in sorted(params.items()))


def label_of(params, keys):
    """Short text of the parameters `keys`: 'lc 6 mm', '10 modes', 'h 1e-04 s', ..."""
    parts = []
    for key in keys:
        value = params[key]
        if key == "crank_lc":
            parts.append(f"lc {value * 1000:g} mm")
        elif key == "conrod_lc":
            parts.append(f"conrod lc {value * 1000:.3g} mm")
        elif key == "order":
            parts.append("Tet4" if value == 1 else "Tet10")
        elif key == "num_modes":
            parts.append(f"{value} modes")
        elif key == "basis":
            parts.append("CB" if value == "craig_bampton" else "RC normal")
        elif key == "rc_set":
            parts.append(f"RC set {value}")
        elif key == "h":
            parts.append(f"h {value:.3g} s")
        elif key == "rho_inf":
            parts.append(f"rho_inf {value:g}")
    return ", ".join(parts)


def build_points(study):
    """Ordered unique points: {'id', 'sweep', 'params', 'families', 'roles', 'label'}."""
    points = {}

    def add(sweep, params, family=None, role=None, label=None):
        key = point_key(sweep, params)
        if key not in points:
            points[key] = {"sweep": sweep, "params": params, "families": [], "roles": [],
                           "label": label or label_of(params, list(params))}
        if family and family not in points[key]["families"]:
            points[key]["families"].append(family)
        if role and role not in points[key]["roles"]:
            points[key]["roles"].append(role)
        return points[key]

    for sweep in SWEEPS:
        if sweep not in study.base:
            continue
        add(sweep, study.resolve(sweep, {}), role="base")
        for name, members, varied in study.families[sweep]:
            for overrides in members:
                params = study.resolve(sweep, overrides)
                point = add(sweep, params, family=name)
                if not point["families"][1:]:
                    point["label"] = label_of(params, varied)
        reference = study.resolve(sweep, study.reference[sweep])
        add(sweep, reference, role="reference")
        for name, overrides in study.checks[sweep]:
            add(sweep, study.resolve(sweep, overrides, base=reference), role=f"check: {name}")
        if sweep == "engine":
            crank_lcs, conrod_lcs = study.auto_candidates() if study.autos else ([], [])
            base = study.base[sweep]
            for name, targets in study.autos:
                params = {"crank_lc": crank_lcs[-1], "conrod_lc": conrod_lcs[-1],
                          "order": base["order"], "basis": "rc_normal",
                          "rc_set": base["rc_set"], "rho_inf": base["rho_inf"], **targets}
                point = add(sweep, params, family=AUTO_FAMILY, label=name)
                point["auto"] = {"crank_lc": crank_lcs, "conrod_lc": conrod_lcs, **targets}
    ordered = list(points.values())
    for point in ordered:
        if "base" in point["roles"] or "reference" in point["roles"] or \
                any(r.startswith("check") for r in point["roles"]):
            point["label"] = label_of(point["params"], list(point["params"]))
    for i, point in enumerate(ordered):
        point["id"] = f"{point['sweep']}_{i + 1:02d}"
    return ordered


# ---------------------------------------------------------------------------------------------
# Meshes

def mesh_name(geo, lc, order):
    stem = os.path.splitext(os.path.basename(geo))[0]
    return f"{stem}_lc{round(lc * 1.0e6)}um_o{order}.msh"


def point_meshes(study, point, input_dir):
    """The (geo, lc, order) meshes a point needs: its crank (and conrod) mesh, or every
    candidate of an automatic-model point."""
    s = study.settings
    p = point["params"]
    crank_geo = os.path.join(input_dir, s["crank_geo"])
    conrod_geo = os.path.join(input_dir, s["conrod_geo"])
    if point.get("auto"):
        return ([(crank_geo, lc, p["order"]) for lc in point["auto"]["crank_lc"]]
                + [(conrod_geo, lc, p["order"]) for lc in point["auto"]["conrod_lc"]])
    needed = [(crank_geo, p["crank_lc"], p["order"])]
    if point["sweep"] == "engine":
        needed.append((conrod_geo, p["conrod_lc"], p["order"]))
    return needed


def count_nodes(path):
    """Number of nodes of an MSH 4.1 ASCII file (the $Nodes header's third number)."""
    with open(path) as stream:
        for line in stream:
            if line.strip() == "$Nodes":
                return int(next(stream).split()[1])
    raise StudyError(f"{path}: no $Nodes section")


def make_meshes(requests, gmsh, work, log):
    """Mesh every (geo, lc, order) once (cached when newer than its .geo); returns
    {(geo, lc, order): (path, nodes, seconds)}. The node count must change with lc."""
    folder = os.path.join(work, "meshes")
    os.makedirs(folder, exist_ok=True)
    meshes = {}
    made = {}                               # path: (geo, lc, order) that made it
    for geo, lc, order in sorted(requests):
        path = os.path.join(folder, mesh_name(geo, lc, order))
        if path in made:                    # the same size to the um, another float
            meshes[(geo, lc, order)] = meshes[made[path]]
            continue
        made[path] = (geo, lc, order)
        seconds = 0.0
        if not (os.path.exists(path) and os.path.getmtime(path) > os.path.getmtime(geo)):
            start = time.perf_counter()
            result = subprocess.run([gmsh, "-3", "-setnumber", "lc", repr(lc), "-setnumber",
                                     "order", str(order), "-format", "msh41", "-o", path, geo],
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            seconds = time.perf_counter() - start
            if result.returncode != 0 or "Error" in result.stdout:
                raise StudyError(f"gmsh failed on {geo} at lc = {lc}, order {order}:\n"
                                 f"{result.stdout[-2000:]}")
            # as the mesh fixtures of input/CMakeLists.txt: curved Tet10 with a distortion
            # (min/max Jacobian ratio) <= 0.2 may be inverted at a quadrature point
            bad = re.findall(r"worst distortion = (-?[0-9.eE+-]+) \(([0-9]+) elements in",
                             result.stdout)
            if any(float(worst) <= 0.0 or int(count) > 0 for worst, count in bad):
                os.remove(path)
                raise StudyError(f"gmsh: {geo} at lc = {lc}, order {order} has elements with "
                                 f"distortion <= 0.2 ({bad}); choose another size")
        nodes = count_nodes(path)
        meshes[(geo, lc, order)] = (path, nodes, seconds)
        log(f"mesh {os.path.basename(path)}: {nodes} nodes ({seconds:.1f} s)")
    by_family = {}
    for path, (geo, lc, order) in made.items():
        by_family.setdefault((geo, order), []).append((lc, meshes[(geo, lc, order)][1]))
    for (geo, order), sizes in by_family.items():
        sizes.sort(reverse=True)
        for (lc_a, n_a), (lc_b, n_b) in zip(sizes, sizes[1:]):
            if n_b <= n_a:
                raise StudyError(f"{geo}, order {order}: lc = {lc_b} gave {n_b} nodes, not more "
                                 f"than the {n_a} of lc = {lc_a}: gmsh did not take the size "
                                 f"(set it with -setnumber lc, see the header of the .geo)")
    return meshes


# ---------------------------------------------------------------------------------------------
# Cases and runs

def crank_interfaces(study, input_dir, rc_set):
    """{interface name: rc} of the crank in the study's rc_cases[rc_set - 1]."""
    cases = study.settings["rc_cases"]
    if not 1 <= rc_set <= len(cases):
        raise StudyError(f"rc_set = {rc_set}: the &study rc_cases list has {len(cases)} files")
    groups = namelist.read(os.path.join(input_dir, cases[rc_set - 1]))
    crank = study.settings["crank_body"]
    return {g.get("name"): g.get("rc", "") for g in namelist.find_all(groups, "interface",
                                                                      body=crank)}


def set_auto_model(body, meshes):
    """Body `body` (a Group) takes the candidate meshes `meshes` (paths, coarse to fine): the
    finest as mesh_file, the others as coarse_meshes; no num_modes (the selection picks)."""
    body.set("mesh_file", meshes[-1])
    if len(meshes) > 1:
        body.set("coarse_meshes", list(meshes[:-1]))
    else:
        body.remove("coarse_meshes")
    body.remove("num_modes")


def model_group(groups):
    """The case's &model group (added when it has none)."""
    found = namelist.find_all(groups, "model")
    if found:
        return found[0]
    group = namelist.Group("model")
    groups.append(group)
    return group


def write_case(study, point, input_dir, meshes, path):
    """The case file of a point, from the base case of its sweep. An engine point with given
    num_modes and h runs with &model selection = 'manual' and no coarse_meshes; an &auto point
    (point['auto']) with selection = 'auto', its targets and candidate meshes, no num_modes on
    the bodies or &modes and no h."""
    s = study.settings
    p = point["params"]
    engine = point["sweep"] == "engine"
    auto = point.get("auto")
    groups = namelist.read(os.path.join(input_dir, s["engine_case" if engine else "crank_case"]))
    run = namelist.find(groups, "run")
    run.set("title", f"study {point['id']}: {point['label']}")
    run.set("output", point["id"] + ".h5")
    crank = namelist.find(groups, "body", name=s["crank_body"])
    crank.set("mesh_file", meshes[(os.path.join(input_dir, s["crank_geo"]), p["crank_lc"],
                                   p["order"])][0])
    rcs = crank_interfaces(study, input_dir, p["rc_set"])
    for group in namelist.find_all(groups, "interface", body=s["crank_body"]):
        if group.get("name") not in rcs:
            raise StudyError(f"rc_set {p['rc_set']}: no crank interface {group.get('name')}")
        group.set("rc", rcs[group.get("name")])
    for body, name, xyz in study.positions:
        if not namelist.find_all(groups, "body", name=body):
            continue                        # e.g. the conrod in a crank-alone case
        found = namelist.find_all(groups, "interface", body=body, name=name)
        if len(found) != 1:
            raise StudyError(f"&position: the case has no &interface body = '{body}', "
                             f"name = '{name}'")
        found[0].set("virtual_node", "position")
        found[0].set("position", xyz)
    modes = namelist.find_all(groups, "modes")
    if not modes:
        modes = [namelist.Group("modes")]
        groups.append(modes[0])
    if auto:
        modes[0].remove("num_modes")
    else:
        modes[0].set("num_modes", p["num_modes"])
    modes[0].set("basis", p["basis"])
    modes[0].set("rc_label", f"RC set {p['rc_set']}")
    if engine:
        conrod = namelist.find(groups, "body", name=s["conrod_body"])
        crank_geo = os.path.join(input_dir, s["crank_geo"])
        conrod_geo = os.path.join(input_dir, s["conrod_geo"])
        model = model_group(groups)
        integrator = namelist.find(groups, "integrator")
        if auto:
            set_auto_model(crank, [meshes[(crank_geo, lc, p["order"])][0]
                                   for lc in auto["crank_lc"]])
            set_auto_model(conrod, [meshes[(conrod_geo, lc, p["order"])][0]
                                    for lc in auto["conrod_lc"]])
            model.items = []
            model.set("selection", "auto")
            model.set("speed_tolerance", float(auto["speed_tolerance"]))
            model.set("force_tolerance", float(auto["force_tolerance"]))
            integrator.remove("h")
        else:
            crank.set("num_modes", p["num_modes"])
            crank.remove("coarse_meshes")
            conrod.set("mesh_file", meshes[(conrod_geo, p["conrod_lc"], p["order"])][0])
            conrod.set("num_modes", p["num_modes"])
            conrod.remove("coarse_meshes")
            model.items = []
            model.set("selection", "manual")
            integrator.set("h", float(p["h"]))
        if s["modal_damping"] > 0.0:
            crank.set("modal_damping", float(s["modal_damping"]))
            conrod.set("modal_damping", float(s["modal_damping"]))
        integrator.set("t_end", float(s["t_end"]))
        integrator.set("rho_inf", float(p["rho_inf"]))
        mechanism = namelist.find(groups, "mechanism")
        mechanism.set("label", point["id"])
        mechanism.set("animation_frames", 0)
        mechanism.set("progress_interval", float(s["t_end"]))
    else:
        run.set("mode_shapes_msh", "none")
    with open(path, "w") as stream:
        stream.write(f"! {point['id']} ({point['sweep']} sweep): {point['label']}\n")
        stream.write(namelist.format_groups(groups))


def wait_for_program(ffrf, limit=900.0):
    """Wait (up to `limit` s) until `ffrf` is an executable file whose size has stayed the same
    for 5 s: another build that relinks it while the study runs leaves it empty or not
    executable for a while."""
    start = time.perf_counter()
    stable, last = 0, None
    while time.perf_counter() - start < limit:
        try:
            size = os.path.getsize(ffrf) if os.access(ffrf, os.X_OK) else None
        except OSError:
            size = None
        stable = stable + 1 if size and size == last else 0
        if stable >= 5:
            return
        last = size
        time.sleep(1.0)
    raise StudyError(f"{ffrf} did not become a stable executable within {limit:.0f} s")


def run_ffrf(ffrf, case, output_dir):
    """(exit code, wall seconds, peak resident memory of the process in MiB). A program that
    cannot be started (being relinked) is waited for, then started again."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    log_path = os.path.splitext(case)[0] + ".log"
    for attempt in range(3):
        try:
            with open(log_path, "w") as log:
                start = time.perf_counter()
                process = subprocess.Popen([ffrf, case, "--output-dir", output_dir],
                                           stdout=log, stderr=subprocess.STDOUT, env=env)
                return finish_ffrf(process, start)
        except OSError as exc:
            if attempt == 2:
                raise StudyError(f"cannot start {ffrf}: {exc}") from exc
            print(f"study_run.py: cannot start {ffrf} ({exc}); waiting for it", flush=True)
            wait_for_program(ffrf)


def finish_ffrf(process, start):
    """Wait for a started ffrf: (exit code, wall seconds, peak memory in MiB)."""
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, wall, usage.ru_maxrss / 1024.0


def measure(study, point, ffrf, input_dir, work, meshes):
    """Run one point; its CSV row."""
    s = study.settings
    p = point["params"]
    folder = os.path.join(work, point["sweep"])
    os.makedirs(folder, exist_ok=True)
    case = os.path.join(folder, point["id"] + ".nml")
    results = os.path.join(folder, point["id"] + ".h5")
    write_case(study, point, input_dir, meshes, case)
    row = {key: "" for key in COLUMNS}
    row.update({"id": point["id"], "sweep": point["sweep"],
                "families": ";".join(point["families"]), "roles": ";".join(point["roles"]),
                "label": point["label"], "case": case, "results": results})
    row.update({k: p.get(k, "") for k in PARAMETERS})
    auto = point.get("auto")
    if not auto:
        row["crank_nodes"] = meshes[(os.path.join(input_dir, s["crank_geo"]), p["crank_lc"],
                                     p["order"])][1]
    if point["sweep"] == "engine" and not auto:
        row["conrod_nodes"] = meshes[(os.path.join(input_dir, s["conrod_geo"]), p["conrod_lc"],
                                      p["order"])][1]
        row["selection"] = "manual"
    if auto:
        row.update({"selection": "auto", "speed_tolerance": auto["speed_tolerance"],
                    "force_tolerance": auto["force_tolerance"], "crank_lc": "",
                    "conrod_lc": ""})
    code, wall, peak = run_ffrf(ffrf, case, folder)
    row.update({"wall_s": wall, "peak_mib": peak})
    if code != 0:
        row["status"] = f"ffrf exit {code} (see {os.path.splitext(case)[0]}.log)"
        return row
    try:
        row.update(study_outputs.stage_summary(results))
        frequencies = study_outputs.crank_frequencies(results, s["crank_body"],
                                                      NUM_FREQUENCIES_MAX)
        for i, value in enumerate(frequencies[:NUM_FREQUENCIES_MAX]):
            row[f"f{i + 1}"] = float(value)
        if point["sweep"] == "engine":
            row.update(study_outputs.engine_outputs(
                results, cycles=int(s["cycles"]), force_joint=s["force_joint"],
                force_side=int(s["force_side"]), force_body=s["force_body"],
                crank_body=s["crank_body"], pin=s["pin_interface"],
                journals=tuple(s["journal_interfaces"])))
            with ffrf_results.open_results(results) as r:
                row["num_coordinates"] = int(r.file["final_state/q"].shape[0])
        if auto:
            row.update(auto_columns(study, point, input_dir, meshes, results))
        row["status"] = "complete"
    except (ffrf_results.ResultsError, ValueError, KeyError, OSError) as exc:
        row["status"] = f"outputs: {exc}"
    return row


def auto_columns(study, point, input_dir, meshes, results):
    """The CSV columns of an automatic-model point from its results file: the choice, the
    predictions, and crank_lc, conrod_lc, node counts, h of the mesh and step taken."""
    s = study.settings
    p = point["params"]
    choice = study_outputs.model_selection(results)
    if choice is None:
        raise ValueError("no /model_selection (or active = 0): the automatic model did not "
                         "run (see the log)")
    columns = {"predicted_force": choice["predicted_force"],
               "predicted_speed": choice["predicted_speed"],
               "predicted_step_force": choice["predicted_step_force"],
               "predicted_step_speed": choice["predicted_step_speed"],
               "auto_h": choice["h"], "h": choice["h"]}
    parts = []
    for role, body, geo in (("crank", s["crank_body"], s["crank_geo"]),
                            ("conrod", s["conrod_body"], s["conrod_geo"])):
        if body not in choice["bodies"]:
            raise ValueError(f"/model_selection has no body {body} (bodies: "
                             f"{', '.join(choice['bodies'])})")
        taken = choice["bodies"][body]
        by_name = {}
        for lc in point["auto"][f"{role}_lc"]:
            path, nodes, _ = meshes[(os.path.join(input_dir, geo), lc, p["order"])]
            by_name[os.path.basename(path)] = (lc, nodes)
        if taken["mesh_file"] not in by_name:
            raise ValueError(f"{body}: mesh {taken['mesh_file']!r} is none of the candidates "
                             f"{', '.join(by_name)}")
        lc, nodes = by_name[taken["mesh_file"]]
        kept = len(taken["kept_modes"])
        columns.update({f"{role}_lc": lc, f"{role}_nodes": nodes, f"{role}_kept_modes": kept})
        if kept:
            hz = ", ".join(f"{f:.0f}" for f in taken["kept_hz"])
            modes = f"{kept} mode{'s' if kept > 1 else ''} ({hz} Hz)"
        else:
            modes = "rigid (no mode)"
        parts.append(f"{body}: lc {lc * 1000:g} mm, {modes}")
    parts.append(f"h {choice['h']:.3g} s")
    columns["auto_model"] = " | ".join(parts)
    return columns


def machine():
    """CPU model, cores, memory of this machine (for the report)."""
    info = {"cores": os.cpu_count(), "platform": platform.platform(),
            "python": platform.python_version()}
    try:
        with open("/proc/cpuinfo") as stream:
            for line in stream:
                if line.startswith("model name"):
                    info["cpu"] = line.split(":", 1)[1].strip()
                    break
        with open("/proc/meminfo") as stream:
            for line in stream:
                if line.startswith("MemTotal"):
                    info["memory_gib"] = round(int(line.split()[1]) / 1024.0**2, 1)
                    break
    except OSError:
        pass
    return info


def write_csv(path, rows):
    with open(path, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=COLUMNS)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in row.items()})


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study", help="study file (input/study.nml)")
    parser.add_argument("--ffrf", required=True, help="the ffrf program")
    parser.add_argument("--gmsh", default="gmsh", help="the gmsh program (default: gmsh)")
    parser.add_argument("--input-dir", default=None,
                        help="folder of the base cases and .geo files (default: the study "
                             "file's folder)")
    parser.add_argument("--work", required=True,
                        help="folder for meshes, cases and results (not in git)")
    parser.add_argument("--csv", required=True, help="write the points here")
    parser.add_argument("--sweep", choices=SWEEPS, action="append",
                        help="run only this sweep (repeatable; default: all)")
    parser.add_argument("--dry-run", action="store_true",
                        help="list the points and meshes, run nothing")
    args = parser.parse_args(argv)
    input_dir = os.path.abspath(args.input_dir or os.path.dirname(os.path.abspath(args.study)))
    work = os.path.abspath(args.work)
    os.makedirs(work, exist_ok=True)
    start = time.perf_counter()

    def log(text):
        print(f"[study {time.perf_counter() - start:7.1f} s] {text}", flush=True)

    try:
        study = Study(args.study)
        points = [p for p in build_points(study) if not args.sweep or p["sweep"] in args.sweep]
        requests = set()
        for point in points:
            requests.update(point_meshes(study, point, input_dir))
        counts = ", ".join(f"{sum(p['sweep'] == s for p in points)} {s}" for s in SWEEPS)
        log(f"{len(points)} points ({counts}), {len(requests)} meshes")
        for point in points:
            tags = "; ".join(point["families"] + point["roles"])
            log(f"  {point['id']}: {point['label']} [{tags}]")
        if args.dry_run:
            return 0
        meshes = make_meshes(requests, args.gmsh, work, log)
        mesh_seconds = sum(m[2] for m in {m[0]: m for m in meshes.values()}.values())
        rows = []
        for i, point in enumerate(points):
            row = measure(study, point, os.path.abspath(args.ffrf), input_dir, work, meshes)
            rows.append(row)
            write_csv(args.csv, rows)
            log(f"{i + 1}/{len(points)} {point['id']} {point['label']}: {row['status']}, "
                f"wall {row['wall_s']:.1f} s, peak {row['peak_mib']:.0f} MiB")
    except (StudyError, namelist.NamelistError) as exc:
        print(f"study_run.py: error: {exc}", file=sys.stderr)
        return 2
    total = time.perf_counter() - start
    meta = {"study": os.path.abspath(args.study), "date": datetime.datetime.now().isoformat(
        timespec="seconds"), "machine": machine(), "total_wall_s": total,
        "mesh_wall_s": mesh_seconds, "num_points": len(rows),
        "failed": [r["id"] for r in rows if r["status"] != "complete"],
        "settings": study.settings}
    with open(os.path.splitext(args.csv)[0] + ".json", "w") as stream:
        json.dump(meta, stream, indent=1)
    log(f"done: {len(rows)} points, {len(meta['failed'])} failed, {total / 60.0:.1f} min "
        f"(meshing {mesh_seconds:.0f} s) -> {args.csv}")
    return 1 if meta["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
