#!/usr/bin/env python3
"""Determinism: two runs of one case on one machine and build give bitwise equal results.

    bitwise.py same DIR_A DIR_B FILE...     every dataset, attribute and view file equal
    bitwise.py digest RESULTS.h5 [FILE ...]  the digests (JSON) that `same` compares

The digest of a results file is the SHA-256 of every dataset (dtype, shape and raw bytes) and of
every attribute, keyed by HDF5 path; Gmsh view files are digested whole. Wall-clock figures are
left out: /timings, /build (library versions), /integrator/wall_seconds and the time statistics
inside the restart state /checkpoint/integrator_reals.

Digests are compared run against run, never against bytes stored in the repository: another
processor or BLAS kernel (OpenBLAS picks one at run time) sums in another order and moves the
last bits. Stored references are compared by value with stated tolerances (results_values.py,
tests/TOLERANCES.md).
"""
import hashlib
import json
import os
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


def same(dir_a, dir_b, files):
    a = digest([os.path.join(dir_a, f) for f in files])
    b = digest([os.path.join(dir_b, f) for f in files])
    problems = []
    for name in files:
        for key in sorted(set(a[name]) | set(b[name])):
            got, want = b[name].get(key), a[name].get(key)
            if got is None or want is None:
                problems.append("%s: %s only in %s" % (name, key, dir_a if got is None else dir_b))
            elif got["sha256"] != want["sha256"]:
                detail = ""
                if want.get("summary") and got.get("summary"):
                    diffs = [abs(x - y) / max(abs(y), 1e-300)
                             for x, y in zip(got["summary"], want["summary"])]
                    detail = " (relative change of sum, norm: %.3g, %.3g)" % tuple(diffs)
                problems.append("%s: %s differs%s" % (name, key, detail))
    count = sum(len(e) for e in a.values())
    if problems:
        print("determinism: %d of %d entries differ between %s and %s:" % (
            len(problems), count, dir_a, dir_b))
        for p in problems:
            print("  " + p)
        return 1
    print("determinism: %d entries of %s bitwise equal in both runs" % (count, ", ".join(files)))
    return 0


def main(argv):
    if len(argv) >= 3 and argv[1] == "digest":
        json.dump(digest(argv[2:]), sys.stdout, indent=0, sort_keys=True)
        sys.stdout.write("\n")
        return 0
    if len(argv) >= 5 and argv[1] == "same":
        return same(argv[2], argv[3], argv[4:])
    print(__doc__)
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
