#!/usr/bin/env python3
"""Results of a run compared by value with a stored reference: regression references that hold
on any x86-64 processor and BLAS kernel (tests/regression/results.cmake).

    results_values.py reference RESULTS.h5 [VIEW.msh VIEW.msh.opt ...] > REFERENCE.json
    results_values.py compare REFERENCE.json RESULTS.h5 [VIEW.msh ...]
    results_values.py spread DIR_A DIR_B FILE...    largest difference per entry, in units of
                                                    its tolerance (to measure TOLERANCES.md)

What is compared (tests/TOLERANCES.md, "Regression references", gives the reasons):
- every HDF5 dataset and attribute of the results file, every number of the Gmsh view files
  (.msh: nodes, elements and each $NodeData block; .opt: the view options), and the text of the
  views with their numbers taken out, which must stay equal;
- strings and integers exactly; floating-point values with the tolerance of the first rule of
  RULES that matches their name: |value - reference| <= atol + rtol * scale, where scale is the
  largest |reference| of the whole dataset (a round-off change of a summation order moves the
  small entries of a dataset by the round-off of its large ones);
- mode shapes with their sign normalised per mode (an eigenvector's sign is not a result:
  another summation order may return -phi);
- round-off diagnostics (eigen residuals, M-orthonormality) as upper bounds, not values;
- wall-clock figures and library versions (bitwise.py's SKIPPED and MASKED), solver counts that
  follow the convergence path and the integrator's restart state are left out.
A reference stores a dataset whole when it is small; a large one by a sample of its entries (a
fixed set of rows or nodes) and, per component (column, mode), its sum, sum of magnitudes,
2-norm, minimum and maximum, each compared with the bound the element tolerance implies
(n tol, n tol, sqrt(n) tol, tol, tol), so that a change anywhere in the dataset is seen.

Determinism (two runs on one machine bitwise equal) is bitwise.py's `same`.
"""
import fnmatch
import hashlib
import json
import math
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bitwise import MASKED, skipped, value_digest  # noqa: E402  (wall-clock entries left out)

# Sample sizes of a stored reference: datasets up to FULL_SIZE entries are stored whole; larger
# ones by SAMPLE_ROWS rows (or nodes) of every component.
FULL_SIZE = 256
SAMPLE_ROWS = 40


class Rule:
    """How one kind of entry is compared. kind: 'value' (|a - r| <= atol + rtol scale),
    'bound' (a <= max(factor r, floor): round-off diagnostics), 'stat' (solver statistics: an
    integer count within rtol, or left out with rtol None). sign_axis: the axis along which
    the values are modes whose sign is free (0: rows of /modes/shape, 1: columns of modal
    coordinates, 'all': the whole entry), or None. reciprocal: compare 1/x (a display factor
    inversely proportional to the largest displacement, which may be round-off). per_component:
    the scale of each component (column) is its own largest |value| (joint reactions: forces and
    moments of very different sizes in one dataset). per_entry: the scale of each entry is its own
    |reference| (frequencies: each relative to itself; the dataset must be stored whole)."""

    def __init__(self, kind, rtol=0.0, atol=0.0, sign_axis=None, factor=None, floor=None,
                 reciprocal=False, per_component=False, per_entry=False):
        self.kind, self.rtol, self.atol = kind, rtol, atol
        self.sign_axis, self.factor, self.floor = sign_axis, factor, floor
        self.reciprocal, self.per_component = reciprocal, per_component
        self.per_entry = per_entry


# First match wins. Patterns are fnmatch patterns on "<file>:<entry>" ("*" matches any text,
# "/" and ":" included). Reasons and measured spreads: tests/TOLERANCES.md.
RULES = [
    # Eigen solver diagnostics: round-off, bounded, not reproduced.
    ("*.h5:bodies/*/modes/residual", Rule("bound", factor=10.0, floor=1e-9)),
    ("*.h5:bodies/*/modes/orthonormality_error", Rule("bound", factor=10.0, floor=1e-12)),
    # Solver statistics: counts that follow the convergence path (a restart more or less on
    # another kernel) or the pivot order; the results they lead to are compared.
    ("*.h5:bodies/*/modes/solver/num_solves", Rule("stat", rtol=0.5)),
    ("*.h5:bodies/*/modes/solver/num_restarts", Rule("stat", rtol=None)),
    ("*.h5:bodies/*/modes/solver/*", Rule("stat", rtol=0.05)),
    # Modes: eigenpairs of a factorisation whose round-off follows the BLAS kernel.
    ("*.h5:*/modes/frequency", Rule("value", rtol=2e-11, per_entry=True)),
    ("*.h5:*/fixed_interface_frequency", Rule("value", rtol=2e-11, per_entry=True)),
    ("*.h5:*/modes/shape", Rule("value", rtol=5e-10, sign_axis=0)),
    ("*.h5:*/modes/virtual_node_shape", Rule("value", rtol=5e-10, sign_axis=0)),
    # The Sturm check's shifts sit just above the top mode (issue 22): as the frequencies.
    ("*.h5:*/modes/sturm_check/shift*", Rule("value", rtol=2e-11, per_entry=True)),
    ("*.h5:model_selection/*_hz", Rule("value", rtol=1e-8, per_entry=True)),
    ("*.h5:model_selection/*", Rule("value", rtol=1e-8)),
    # Time histories of a mechanism run: states converged to newton_rtol = 1e-8 per step, whose
    # differences add up along the crank angle's neutral direction over the run's steps.
    ("*.h5:time/crank_angle", Rule("value", atol=1e-6)),
    ("*.h5:final_state/crank_angle", Rule("value", atol=1e-6)),
    ("*.h5:checkpoint/crank_reference", Rule("value", atol=1e-6)),
    ("*.h5:time/*", Rule("value", rtol=1e-6)),
    # the engine's crank sensors: the numbers of /time/crank_angle and /time/crank_speed
    ("*.h5:sensors/crank_angle", Rule("value", atol=1e-6)),
    ("*.h5:sensors/crank_speed", Rule("value", rtol=1e-6)),
    ("*.h5:sensors/*", Rule("value", rtol=1e-6, atol=1e-12, per_component=True)),
    ("*.h5:bodies/*/position", Rule("value", rtol=1e-6, atol=1e-12)),
    ("*.h5:bodies/*/euler_parameters", Rule("value", rtol=1e-6, atol=1e-12)),
    ("*.h5:bodies/*/modal_coordinates", Rule("value", rtol=1e-6, atol=1e-10, sign_axis=1)),
    ("*.h5:energy/*_dissipation", Rule("value", rtol=1e-5, atol=1e-9)),
    ("*.h5:energy/strain", Rule("value", rtol=1e-6, atol=1e-12)),
    ("*.h5:energy/*", Rule("value", rtol=1e-6)),
    ("*.h5:final_state/*", Rule("value", rtol=1e-6)),
    # Reactions: per component (forces and moments); the engines' near-redundant rows carry
    # multipliers of up to 5e9 N m whose round-off the Jacobian's conditioning amplifies.
    ("*.h5:joints/*/reaction", Rule("value", rtol=1e-3, atol=1e-2, per_component=True)),
    ("*.h5:integrator/counters", Rule("stat", rtol=0.01)),
    ("*.h5:integrator/max_constraint_violation", Rule("bound", factor=10.0, floor=1e-12)),
    # The integrator's restart state holds its Newton history and LU pivot order, which follow
    # the round-off; restarts are checked run against run (regression_slurm_array, ...).
    ("*.h5:checkpoint/integrator_*", Rule("stat", rtol=None)),
    # The restart fingerprint (docs/restart.md): checked entry by entry by restarting
    # (regression_restart_fingerprint), not against stored text.
    ("*.h5:checkpoint/fingerprint_*", Rule("stat", rtol=None)),
    ("*.h5:checkpoint/*", Rule("value", rtol=1e-6, atol=1e-9)),
    # Gmsh views: mode shapes (sign free per view), deformation over time (7 printed digits).
    ("*_modes.msh:$NodeData*", Rule("value", rtol=5e-10, sign_axis="all")),
    ("*_animation.msh:$NodeData*", Rule("value", rtol=2e-6, atol=1e-12)),
    ("*_animation.msh.opt:*DisplacementFactor", Rule("value", atol=1e-9, reciprocal=True)),
    ("*.msh.opt:*", Rule("value", rtol=1e-6)),
    # Everything else (geometry, masses, interface data, inputs): round-off of sums.
    ("*", Rule("value", rtol=1e-12)),
]


def rule_for(name):
    for pattern, rule in RULES:
        if fnmatch.fnmatchcase(name, pattern):
            return rule
    raise AssertionError("no rule for " + name)


# ---------------------------------------------------------------------------------------------
# Reading a run's files into entries: name -> numpy array (numbers) or bytes (text)

def read_h5(path, entries):
    file = os.path.basename(path)
    with h5py.File(path, "r") as f:
        for key, value in f.attrs.items():
            entries[file + ":@" + key] = value

        def visit(name, obj):
            if skipped(name):
                return
            for key, value in obj.attrs.items():
                entries[file + ":" + name + "@" + key] = value
            if isinstance(obj, h5py.Dataset):
                value = obj[()]
                if name in MASKED:
                    value = np.array(value)
                    value[MASKED[name]] = 0.0
                entries[file + ":" + name] = value

        f.visititems(visit)


NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?|"
                    r"\d+[eE][-+]?\d+|nan|inf)(?![\w.])", re.IGNORECASE)
QUOTED = re.compile(r'"[^"]*"')


def numbers_of(line):
    """The floating-point numbers of a line (integers and quoted strings are text)."""
    return [float(x) for x in NUMBER.findall(QUOTED.sub(" ", line))]


def text_of(line):
    """The line with its floating-point numbers taken out and its blanks normalised (a sign
    change moves the columns of a formatted number)."""
    parts = QUOTED.split(line)
    quoted = QUOTED.findall(line)
    out = []
    for i, part in enumerate(parts):
        out.append(NUMBER.sub("#", part))
        if i < len(quoted):
            out.append(quoted[i])
    return " ".join("".join(out).split())


def read_msh_view(path, file, entries):
    """A Gmsh view file (MSH 2.2 ASCII): the numbers of $Nodes and of each $NodeData block (its
    real tags apart from its values), each section an entry."""
    section, numbers, tags = "", [], []
    counts = {}
    # a $NodeData block opens with three counted groups of tags (strings, reals, integers):
    # group is the one being read, remaining its lines still to come (None: its count comes next)
    group, remaining = 3, None

    def close():
        if tags:
            entries[file + ":" + section + "/tags"] = np.array(tags)
        if numbers:
            entries[file + ":" + section] = np.array(numbers)

    with open(path, "r") as f:
        lines = f.read().splitlines()
    skeleton = []
    for line in lines:
        skeleton.append(text_of(line))
        if line.startswith("$End"):
            close()
            section, numbers, tags, group = "", [], [], 3
        elif line.startswith("$"):
            name = line[1:].strip()
            counts[name] = counts.get(name, 0) + 1
            section, numbers, tags = "$%s[%d]" % (name, counts[name]), [], []
            group = 0 if name in ("NodeData", "ElementData", "ElementNodeData") else 3
            remaining = None
        elif group < 3:
            if remaining is None:
                remaining = int(line.split()[0])
            else:
                if group == 1:
                    tags.extend(numbers_of(line))
                remaining -= 1
            if remaining == 0:
                group, remaining = group + 1, None
        else:
            numbers.extend(numbers_of(line))
    close()
    entries[file + ":<text without numbers>"] = "\n".join(skeleton).encode()


def read_opt(path, file, entries):
    """Gmsh view options (.opt): each assignment with numbers is an entry."""
    skeleton = []
    with open(path, "r") as f:
        for line in f.read().splitlines():
            skeleton.append(text_of(line))
            found = numbers_of(line.split("//")[0])
            if found and "=" in line:
                entries[file + ":" + line.split("=")[0].strip()] = np.array(found)
    entries[file + ":<text without numbers>"] = "\n".join(skeleton).encode()


def read_files(paths):
    entries = {}
    for path in paths:
        if path.endswith(".h5"):
            read_h5(path, entries)
        elif path.endswith(".opt"):
            read_opt(path, os.path.basename(path), entries)
        else:
            read_msh_view(path, os.path.basename(path), entries)
    return entries


def is_float(value):
    return isinstance(value, np.ndarray) and value.dtype.kind == "f" or isinstance(value, float)


def exact_digest(value):
    if isinstance(value, (bytes, str)):
        data = value.encode() if isinstance(value, str) else value
        return hashlib.sha256(b"text " + data).hexdigest()
    return value_digest(value)


def readable(value):
    """A small exact value as JSON, for people reading a reference file."""
    if isinstance(value, bytes):
        return value.decode(errors="replace") if len(value) <= 200 else None
    array = np.asarray(value)
    if array.dtype.kind == "S":
        return [x.decode(errors="replace") for x in array.ravel()][:20]
    if array.dtype.kind in "iu" and array.size <= 20:
        return array.ravel().tolist()
    return None


# ---------------------------------------------------------------------------------------------
# Floating-point datasets: components, samples, statistics

def as_components(array, rule):
    """The dataset as a 2-D array (rows, components): the sign axis (modes) or the last axis of a
    2-D dataset become the components; 1-D data is one component."""
    array = np.asarray(array, dtype=float)
    if array.ndim == 0:
        return array.reshape(1, 1)
    if rule.sign_axis == "all" or array.ndim == 1:
        return array.reshape(-1, 1)
    if array.ndim > 2:
        array = array.reshape(array.shape[0], -1)
    return array.T if rule.sign_axis == 0 else array


def sample_rows(num_rows):
    if num_rows <= SAMPLE_ROWS:
        return list(range(num_rows))
    return sorted(set(int(round(x)) for x in np.linspace(0, num_rows - 1, SAMPLE_ROWS)))


def statistics(data):
    with np.errstate(all="ignore"):
        return {"sum": data.sum(axis=0), "sumabs": np.abs(data).sum(axis=0),
                "norm": np.sqrt((data * data).sum(axis=0)), "min": data.min(axis=0),
                "max": data.max(axis=0)}


def float_values(array, rule):
    array = np.asarray(array, dtype=float)
    if rule.reciprocal:
        with np.errstate(divide="ignore"):
            array = 1.0 / array
    return array


def float_reference(array, rule):
    array = float_values(array, rule)
    data = as_components(array, rule)
    if rule.per_component and data.size:
        scale = np.nanmax(np.abs(data), axis=0).tolist()
    else:
        scale = float(np.nanmax(np.abs(data))) if data.size else 0.0
    ref = {"shape": list(array.shape), "scale": scale}
    if array.size <= FULL_SIZE:
        ref["values"] = data.tolist()
        return ref
    rows = sample_rows(data.shape[0])
    ref["rows"] = rows
    ref["values"] = data[rows].tolist()
    ref["statistics"] = {k: v.tolist() for k, v in statistics(data).items()}
    return ref


def tolerance(rule, scale):
    return rule.atol + rule.rtol * scale


def compare_float(name, rule, ref, array):
    """Problems of a floating-point entry against its reference (empty when within tolerance),
    and the largest difference in units of the tolerance."""
    array = float_values(array, rule)
    if list(array.shape) != ref["shape"]:
        return ["%s: shape %s, reference %s" % (name, list(array.shape), ref["shape"])], math.inf
    data = as_components(array, rule)
    expected = np.array(ref["values"], dtype=float).reshape(-1, data.shape[1]) \
        if data.size else np.zeros((0, data.shape[1]))
    rows = ref.get("rows", list(range(data.shape[0])))
    got = data[rows]
    if not np.all(np.isfinite(got)) and not np.array_equal(np.isnan(got), np.isnan(expected)):
        return ["%s: not finite where the reference is" % name], math.inf
    if rule.kind == "bound":
        limit = np.maximum(rule.factor * np.abs(expected), rule.floor)
        over = got - limit
        worst = float(np.nanmax(got / limit)) if got.size else 0.0
        if np.any(over > 0):
            return ["%s: %.3g exceeds its bound %.3g (%g x the reference %.3g, or %g)" % (
                name, got.ravel()[np.argmax(over)], limit.ravel()[np.argmax(over)], rule.factor,
                expected.ravel()[np.argmax(over)], rule.floor)], worst
        return [], worst
    tol = tolerance(rule, np.asarray(ref["scale"], dtype=float))
    tol_of = np.broadcast_to(tol, (data.shape[1],))
    sign = np.ones(data.shape[1])
    if rule.sign_axis is not None:
        sign = np.where((got * expected).sum(axis=0) < 0.0, -1.0, 1.0)
    diff = np.abs(got * sign - expected)
    if rule.per_entry:
        if "statistics" in ref:
            raise AssertionError(name + ": per-entry tolerances need the dataset stored whole")
        tol_of = tolerance(rule, np.abs(expected))
    problems, worst = [], 0.0
    with np.errstate(all="ignore"):
        units = np.where(diff == 0.0, 0.0, diff / np.maximum(tol_of, 1e-300))
    units = np.nan_to_num(units, nan=0.0)
    if units.size:
        worst = float(units.max())
    if worst > 1.0:
        at = np.unravel_index(np.argmax(units), units.shape)
        problems.append("%s: %.17g where the reference has %.17g (row %d, component %d): "
                        "difference %.3g > tolerance %.3g (atol %g + rtol %g x scale %.6g)" % (
                            name, got[at] * sign[at[1]], expected[at], rows[at[0]], at[1],
                            diff[at], np.broadcast_to(tol_of, diff.shape)[at], rule.atol,
                            rule.rtol, np.abs(expected[at]) if rule.per_entry else
                            np.broadcast_to(ref["scale"], (data.shape[1],))[at[1]]))
    if "statistics" in ref:
        n = data.shape[0]
        now = statistics(data)
        flipped = sign < 0
        now["sum"] = now["sum"] * sign
        low, high = now["min"].copy(), now["max"].copy()
        now["min"] = np.where(flipped, -high, low)
        now["max"] = np.where(flipped, -low, high)
        bounds = {"sum": n * tol_of, "sumabs": n * tol_of, "norm": math.sqrt(n) * tol_of,
                  "min": tol_of, "max": tol_of}
        for key, bound in bounds.items():
            delta = np.abs(now[key] - np.array(ref["statistics"][key], dtype=float))
            with np.errstate(all="ignore"):
                ratio = np.where(delta == 0.0, 0.0, delta / np.maximum(bound, 1e-300))
            ratio = np.nan_to_num(ratio, nan=0.0)
            worst = max(worst, float(ratio.max()))
            if ratio.max() > 1.0:
                component = int(np.argmax(ratio))
                problems.append("%s: %s of component %d is %.17g, reference %.17g: difference "
                                "%.3g > %.3g" % (name, key, component, now[key][component],
                                                 ref["statistics"][key][component],
                                                 delta[component], bound[component]))
    return problems, worst


# ---------------------------------------------------------------------------------------------
# Commands

def make_reference(paths):
    reference = {}
    for name, value in sorted(read_files(paths).items()):
        rule = rule_for(name)
        if rule.kind == "stat" and rule.rtol is None:
            continue
        numeric = isinstance(value, (np.ndarray, np.generic)) and value.dtype.kind in "fiu"
        if is_float(value) and rule.kind != "stat":
            entry = {"compare": rule.kind}
            entry.update(float_reference(value, rule))
        elif rule.kind == "stat" and numeric:
            entry = {"compare": "stat", "value": np.asarray(value).astype(float).ravel().tolist()}
        else:
            entry = {"compare": "exact", "sha256": exact_digest(value)}
            shown = readable(value)
            if shown is not None:
                entry["value"] = shown
        reference[name] = entry
    return reference


def compare_entries(reference, entries):
    problems, worst = [], {}
    for name, ref in reference.items():
        if name not in entries:
            problems.append("%s: missing (the reference has it)" % name)
            continue
        value, rule = entries[name], rule_for(name)
        if ref["compare"] == "exact":
            if exact_digest(value) != ref["sha256"]:
                shown = readable(value)
                problems.append("%s: differs from the reference%s" % (
                    name, "" if shown is None else " (now %s, reference %s)" % (
                        shown, ref.get("value"))))
        elif ref["compare"] == "stat" and rule.kind == "stat":
            now = np.asarray(value).astype(float).ravel()
            was = np.array(ref["value"], dtype=float)
            if now.shape != was.shape or np.any(np.abs(now - was) > rule.rtol * np.abs(was)):
                problems.append("%s: %s, reference %s (allowed %g relative)" % (
                    name, now.tolist(), was.tolist(), rule.rtol))
        else:
            found, worst[name] = compare_float(name, rule, ref, value)
            problems.extend(found)
    for name, value in entries.items():
        rule = rule_for(name)
        if name not in reference and not (rule.kind == "stat" and rule.rtol is None):
            problems.append("%s: new (not in the reference)" % name)
    return problems, worst


def compare(reference_path, paths):
    with open(reference_path) as f:
        reference = json.load(f)
    problems, worst = compare_entries(reference, read_files(paths))
    if problems:
        print("results_values: %d of %d entries differ from %s:" % (
            len(problems), len(reference), reference_path))
        for p in problems:
            print("  " + p)
        return 1
    name = max(worst, key=worst.get) if worst else "-"
    print("results_values: %d entries equal the reference %s within their tolerances (closest "
          "to its tolerance: %s at %.2g of it)" % (len(reference), reference_path, name,
                                                   worst.get(name, 0.0)))
    return 0


def spread(dir_a, dir_b, files):
    """How far run B is from run A, per floating-point entry: the largest difference over the
    whole dataset (mode signs normalised) relative to the dataset's largest |value| and in units
    of its tolerance; then the problems the comparison with A as reference would report."""
    a = read_files([os.path.join(dir_a, f) for f in files])
    b = read_files([os.path.join(dir_b, f) for f in files])
    rows = []
    for name in sorted(set(a) & set(b)):
        rule = rule_for(name)
        if not is_float(a[name]) or rule.kind != "value" or np.shape(a[name]) != np.shape(b[name]):
            continue
        x, y = as_components(float_values(a[name], rule), rule), \
            as_components(float_values(b[name], rule), rule)
        if rule.sign_axis is not None:
            y = y * np.where((x * y).sum(axis=0) < 0.0, -1.0, 1.0)
        if not x.size:
            continue
        if rule.per_entry:
            scale, diff = np.abs(x), np.abs(x - y)
        else:
            scale = np.nanmax(np.abs(x), axis=0) if rule.per_component else \
                np.full(x.shape[1], np.nanmax(np.abs(x)))
            diff = np.nanmax(np.abs(x - y), axis=0)
        with np.errstate(all="ignore"):
            units = np.nan_to_num(np.where(diff == 0, 0.0, diff / tolerance(rule, scale)))
            relative = np.nan_to_num(np.where(diff == 0, 0.0, diff / scale))
        rows.append((float(units.max()), float(relative.max()), float(diff.max()), name))
    print("%10s %10s %10s  %s" % ("tolerances", "relative", "absolute", "entry"))
    for row in sorted(rows, reverse=True):
        print("%10.3g %10.3g %10.3g  %s" % row)
    problems, _ = compare_entries(make_reference([os.path.join(dir_a, f) for f in files]), b)
    for p in problems:
        print("PROBLEM " + p)
    return 1 if problems else 0


def main(argv):
    if len(argv) >= 3 and argv[1] == "reference":
        json.dump(make_reference(argv[2:]), sys.stdout, indent=0, sort_keys=True)
        sys.stdout.write("\n")
        return 0
    if len(argv) >= 4 and argv[1] == "compare":
        return compare(argv[2], argv[3:])
    if len(argv) >= 5 and argv[1] == "spread":
        return spread(argv[2], argv[3], argv[4:])
    print(__doc__)
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
