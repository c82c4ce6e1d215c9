#!/usr/bin/env python3
"""Bitwise comparison of a run's results with digests made before a change.

    bitwise.py digest  RESULTS.h5 [FILE.msh ...] > REFERENCE.json
    bitwise.py compare REFERENCE.json RESULTS.h5 [FILE.msh ...]

The digest of a results file is the SHA-256 of every dataset (dtype, shape and raw bytes) and of
every attribute, keyed by HDF5 path; Gmsh view files (.msh) are digested whole. Wall-clock
figures are left out: /timings, /build (library versions), /integrator/wall_seconds and the
time statistics inside the restart state /checkpoint/integrator_reals. A reference
digest states "these numbers are the numbers of revision X": any change of any value, even in the
last bit, fails the comparison, which then lists the datasets that differ (with the largest
relative difference when the file's values can still be compared with the reference's sums).
The digests hold for this toolchain (Debian 12's gfortran 12, MUMPS, OpenBLAS) on x86-64.
"""
import hashlib
import json
import sys

import h5py
import numpy as np

SKIPPED = ("timings", "build", "integrator/wall_seconds")
# Wall-clock entries inside a dataset: the integrator's restart state (galpha_export_state) holds
# its time statistics at reals(8:12) (wall, residual, tangent, factor and solve seconds)
MASKED = {"checkpoint/integrator_reals": slice(7, 12)}


def skipped(name):
    return any(name == s or name.startswith(s + "/") for s in SKIPPED)


def value_digest(value):
    array = np.asarray(value)
    if array.dtype.kind in "fiu":
        array = array.astype(array.dtype.newbyteorder("<"))
    head = "%s %s " % (array.dtype.str, array.shape)
    return hashlib.sha256(head.encode() + array.tobytes()).hexdigest()


def summary(value):
    """Sum and 2-norm of a numeric dataset, to tell round-off from a real change on failure."""
    array = np.asarray(value)
    if array.dtype.kind not in "fiu" or array.size == 0:
        return None
    array = array.astype(float)
    return [float(array.sum()), float(np.sqrt((array * array).sum()))]


def digest_h5(path):
    entries = {}
    with h5py.File(path, "r") as f:
        for key, value in f.attrs.items():
            entries["@" + key] = {"sha256": value_digest(value)}

        def visit(name, obj):
            if skipped(name):
                return
            for key, value in obj.attrs.items():
                entries[name + "@" + key] = {"sha256": value_digest(value)}
            if isinstance(obj, h5py.Dataset):
                value = obj[()]
                if name in MASKED:
                    value = np.array(value)
                    value[MASKED[name]] = 0.0
                entries[name] = {"sha256": value_digest(value), "summary": summary(value)}

        f.visititems(visit)
    return entries


def digest_file(path):
    with open(path, "rb") as f:
        return {"sha256": hashlib.sha256(f.read()).hexdigest()}


def digest(paths):
    result = {}
    for path in paths:
        name = path.rsplit("/", 1)[-1]
        result[name] = digest_h5(path) if path.endswith(".h5") else {"<file>": digest_file(path)}
    return result


def compare(reference_path, paths):
    with open(reference_path) as f:
        reference = json.load(f)
    now = digest(paths)
    problems = []
    for name, entries in reference.items():
        if name not in now:
            problems.append("%s: not given (the reference digests it)" % name)
            continue
        for key, ref in entries.items():
            got = now[name].get(key)
            if got is None:
                problems.append("%s: %s missing" % (name, key))
            elif got["sha256"] != ref["sha256"]:
                detail = ""
                if ref.get("summary") and got.get("summary"):
                    diffs = [abs(a - b) / max(abs(b), 1e-300) for a, b in zip(got["summary"], ref["summary"])]
                    detail = " (relative change of sum, norm: %.3g, %.3g)" % tuple(diffs)
                problems.append("%s: %s differs%s" % (name, key, detail))
        for key in now[name]:
            if key not in entries:
                problems.append("%s: %s is new (not in the reference)" % (name, key))
    for name in now:
        if name not in reference:
            problems.append("%s: no reference digest" % name)
    count = sum(len(e) for e in reference.values())
    if problems:
        print("bitwise: %d of %d entries differ from %s:" % (len(problems), count, reference_path))
        for p in problems:
            print("  " + p)
        return 1
    print("bitwise: %d entries of %s equal the reference %s" % (count, ", ".join(now), reference_path))
    return 0


def main(argv):
    if len(argv) >= 3 and argv[1] == "digest":
        json.dump(digest(argv[2:]), sys.stdout, indent=0, sort_keys=True)
        sys.stdout.write("\n")
        return 0
    if len(argv) >= 4 and argv[1] == "compare":
        return compare(argv[2], argv[3:])
    print(__doc__)
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
