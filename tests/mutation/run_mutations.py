#!/usr/bin/env python3
"""Mutation check (issue 13, item 1): break the code on purpose, one mutation at a time, and see
that the related tests fail.

Usage (documented in tests/mutation/README.md; also `cmake --build build/release --target
mutation`):

    python3 tests/mutation/run_mutations.py [--work DIR] [--only ID[,ID...]] [--jobs N]

The source tree (this repository minus build*/, .git, results/) is copied once into
WORK/source (default: $TMPDIR/ffrf-mutation); later runs copy only the files that differ, so
the build stays incremental. One build is configured in WORK/build: Release at -O2 without the
driver's link-time optimisation (-DFFRF_LTO=OFF), Ninja. The unmutated targets are built and the
union of all related tests run once (baseline, with their mesh fixtures). Then for each entry of
mutations.toml: the `find` text (exactly once in `file`, else the entry is broken) is replaced,
only the executables of the related tests are rebuilt, those tests run (ctest -R <tests>,
never the _checked variants, the determinism tests nor the forced-kernel results_* tests, with
their mesh fixtures (gmsh again: a mesh the baseline made is not relied on), stop on the first
failure; output in WORK/logs/ID.log), and the file is
restored. A table of caught / survived / broken per entry with the test that caught it and the
seconds it took is printed; the exit status is 1 when any entry survived or is broken, 0
otherwise. Standard library only (Python >= 3.11 for tomllib).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

EXCLUDE = r"_checked$|^determinism_|^results_.*_(haswell|sandybridge|nehalem)$"
SKIP_DIRS = {".git", "results", "_install", "__pycache__"}


def run(cmd, **kwargs):
    return subprocess.run(cmd, text=True, capture_output=True, **kwargs)


def sync_tree(source, target):
    """Copy source to target, only the files whose bytes differ (mtimes kept otherwise)."""
    copied = 0
    for root, dirs, files in os.walk(source):
        rel = Path(root).relative_to(source)
        dirs[:] = [d for d in dirs if d not in SKIP_DIRS
                   and not (rel == Path(".") and d.startswith("build"))
                   and not (Path(root) / d / "CMakeCache.txt").exists()]
        (target / rel).mkdir(parents=True, exist_ok=True)
        for name in files:
            src, dst = Path(root) / name, target / rel / name
            data = src.read_bytes()
            if not dst.exists() or dst.read_bytes() != data:
                dst.write_bytes(data)
                shutil.copymode(src, dst)
                copied += 1
    return copied


def load_list(path):
    with open(path, "rb") as f:
        entries = tomllib.load(f)["mutation"]
    for e in entries:
        for key in ("id", "file", "find", "replace", "tests", "why"):
            if key not in e:
                sys.exit(f"{path}: entry {e.get('id', '?')} has no '{key}'")
    ids = [e["id"] for e in entries]
    if len(ids) != len(set(ids)):
        sys.exit(f"{path}: duplicate ids")
    return entries


def ctest_tests(build, regex, ctest):
    """The tests ctest selects for regex (with the fixtures they require), as (name, command)."""
    out = run([ctest, "--test-dir", str(build), "-R", regex, "-E", EXCLUDE,
               "--show-only=json-v1"])
    if out.returncode != 0:
        raise RuntimeError(out.stderr)
    return [(t["name"], t.get("command", [])) for t in json.loads(out.stdout)["tests"]]


def exact(names):
    """A ctest regex that selects exactly these tests: ^name$ alternatives without groups (CMake's
    regex engine allows at most 9 subexpressions, so "(a)|(b)|..." of 10 or more entries selects
    nothing)."""
    return "|".join("^" + re.sub(r"([.+*?^$\\[\]()|{}])", r"\\\1", name) + "$"
                    for name in names)


def ninja_targets(build):
    out = run(["ninja", "-C", str(build), "-t", "targets", "all"])
    return {line.split(":")[0] for line in out.stdout.splitlines() if ": phony" in line}


def build_targets(tests, targets):
    """Every built executable a test runs: any word of its command (split at ';' and '=', for
    cmake -E env and cmake -P wrappers) whose file name is a build target; the driver for tests
    that are scripts around it."""
    wanted = set()
    for name, command in tests:
        found = False
        for argument in command:
            for word in re.split(r"[;=]", argument):
                base = os.path.basename(word)
                if base in targets:
                    wanted.add(base)
                    found = True
        if name in targets:
            wanted.add(name)
            found = True
        if not found and not name.startswith("mesh_") and "_gmsh_" not in name:
            wanted.add("ffrf")
    return sorted(wanted)


def run_tests(build, names, ctest, jobs, stop_on_failure):
    """Run exactly the tests `names`; (return code, failed tests, tests that ran to an end,
    log)."""
    cmd = [ctest, "--test-dir", str(build), "-R", exact(names), "-j", str(jobs),
           "--output-on-failure", "--no-tests=error", "--timeout", "600"]
    if stop_on_failure:
        cmd += ["--stop-on-failure"]
    out = run(cmd, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    # "Not Run" entries are the ones --stop-on-failure skipped (or whose program is missing)
    failed = re.findall(r"^\s*\d+ - (\S+) \((?!Not Run)", out.stdout.split("tests FAILED:")[-1],
                        re.M) if "tests FAILED:" in out.stdout else []
    ran = re.findall(r"Test +#\d+: (\S+) \.+\s*(?:\*\*\*)?(?!Not Run)\w", out.stdout)
    return out.returncode, failed, ran, out.stdout + out.stderr


def entry_problem(e, source):
    """Why the entry cannot be applied to the sources (None: it can)."""
    path = source / e["file"]
    if not e["file"].startswith("src/") or not path.is_file():
        return f"no file {e['file']} under src/"
    count = path.read_text().count(e["find"])
    if count != 1:
        return f"find text occurs {count} times in {e['file']}"
    return None


def check_list(entries, source, build, ctest):
    """Exit status 0 when every entry applies as written (a moved or edited line breaks an entry
    silently until the next full mutation run: this check runs in ctest)."""
    problems = []
    for e in entries:
        problem = entry_problem(e, source)
        if problem is None and not ctest_tests(build, e["tests"], ctest):
            problem = f"no test matches '{e['tests']}'"
        if problem:
            problems.append(f"{e['id']}: {problem}")
    for line in problems:
        print("broken entry " + line)
    print(f"mutation list: {len(entries)} entries, {len(problems)} broken")
    return 1 if problems else 0


def main():
    here = Path(__file__).resolve().parent
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path, default=here.parent.parent,
                        help="repository root (default: this script's)")
    parser.add_argument("--work", type=Path,
                        default=Path(tempfile.gettempdir()) / "ffrf-mutation",
                        help="scratch folder (outside the repository's sources)")
    parser.add_argument("--list", type=Path, default=here / "mutations.toml")
    parser.add_argument("--only", default="", help="comma-separated ids")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--cmake", default="cmake")
    parser.add_argument("--ctest", default="ctest")
    parser.add_argument("--generator", default="Ninja")
    parser.add_argument("--check-list", type=Path, metavar="BUILD",
                        help="only check that every entry applies (its file under src/, its find "
                        "text there exactly once, its tests regex selecting a test of the build "
                        "folder BUILD), without building or mutating: ctest mutation_list_applies")
    args = parser.parse_args()

    entries = load_list(args.list)
    if args.check_list:
        sys.exit(check_list(entries, args.source.resolve(), args.check_list, args.ctest))
    if args.only:
        keep = set(args.only.split(","))
        unknown = keep - {e["id"] for e in entries}
        if unknown:
            sys.exit(f"unknown ids: {', '.join(sorted(unknown))}")
        entries = [e for e in entries if e["id"] in keep]
    source, build = args.work / "source", args.work / "build"
    start = time.monotonic()
    copied = sync_tree(args.source.resolve(), source)
    print(f"mutation: {copied} files copied to {source}", flush=True)
    if not (build / "CMakeCache.txt").exists():
        out = run([args.cmake, "-S", str(source), "-B", str(build), "-G", args.generator,
                   "-DCMAKE_BUILD_TYPE=Release", "-DFFRF_LTO=OFF",
                   "-DCMAKE_Fortran_FLAGS_RELEASE=-O2", "-DCMAKE_C_FLAGS_RELEASE=-O2"])
        if out.returncode != 0:
            sys.exit("mutation: configure failed\n" + out.stdout + out.stderr)
    else:
        run([args.cmake, str(build)])

    results = {}
    logs = args.work / "logs"
    logs.mkdir(exist_ok=True)
    targets = ninja_targets(build)
    plan = []
    for e in entries:
        problem = entry_problem(e, source)
        if problem:
            results[e["id"]] = ("broken", problem, 0.0)
            continue
        tests = ctest_tests(build, e["tests"], args.ctest)
        if not tests:
            results[e["id"]] = ("broken", f"no test matches '{e['tests']}'", 0.0)
            continue
        plan.append((e, [name for name, _ in tests], build_targets(tests, targets)))

    if plan:
        all_targets = sorted({t for _, _, ts in plan for t in ts})
        union = sorted({name for _, tests, _ in plan for name in tests})
        print(f"mutation: baseline build of {len(all_targets)} targets", flush=True)
        out = run([args.cmake, "--build", str(build), "-j", str(args.jobs), "--target",
                   *all_targets])
        if out.returncode != 0:
            sys.exit("mutation: the unmutated build failed\n" + out.stdout[-5000:])
        code, failed, ran, log = run_tests(build, union, args.ctest, args.jobs, False)
        missing = sorted(set(union) - set(ran))
        if missing:
            print(log[-5000:])
            sys.exit(f"mutation: the baseline selected {len(union)} tests but "
                     f"{len(missing)} did not run: {', '.join(missing[:10])}")
        if code != 0:
            print(log[-5000:])
            for e, tests, _ in plan:
                bad = [t for t in tests if t in failed]
                if bad:
                    results[e["id"]] = ("broken", "fails unmutated: " + ",".join(bad), 0.0)
            plan = [p for p in plan if p[0]["id"] not in results]
        print(f"mutation: baseline ran {len(ran)} of {len(union)} selected tests and passed "
              f"({time.monotonic() - start:.0f} s); {len(plan)} mutations", flush=True)

    for e, tests, wanted in plan:
        path = source / e["file"]
        original = path.read_text()
        t0 = time.monotonic()
        try:
            path.write_text(original.replace(e["find"], e["replace"]))
            out = run([args.cmake, "--build", str(build), "-j", str(args.jobs), "--target",
                       *wanted])
            if out.returncode != 0:
                result = ("broken", "does not compile")
            else:
                code, failed, ran, log = run_tests(build, tests, args.ctest, args.jobs, True)
                (logs / f"{e['id']}.log").write_text(log)
                if code == 0 and len(set(ran)) != len(tests):
                    # a survivor must have run every test it names
                    result = ("broken", f"{len(set(ran))} of {len(tests)} tests ran")
                elif code == 0:
                    result = ("survived", f"{len(tests)} tests")
                elif failed:
                    result = ("caught", ",".join(failed) + f" (of {len(tests)} tests)")
                else:
                    result = ("broken", "ctest error: " + log.strip().splitlines()[-1])
        finally:
            path.write_text(original)
        results[e["id"]] = (*result, time.monotonic() - t0)
        print(f"  {e['id']}: {result[0]} {result[1]} ({results[e['id']][2]:.0f} s)",
              flush=True)

    print()
    width = max(len(e["id"]) for e in entries)
    fwidth = max(len(e["file"]) for e in entries)
    print(f"{'id':<{width}}  {'file':<{fwidth}}  {'result':<8}  {'s':>5}  caught by / reason")
    for e in entries:
        status, detail, seconds = results[e["id"]]
        print(f"{e['id']:<{width}}  {e['file']:<{fwidth}}  {status:<8}  {seconds:5.0f}  "
              f"{detail}")
    counts = {s: sum(r[0] == s for r in results.values())
              for s in ("caught", "survived", "broken")}
    print(f"\n{counts['caught']} caught, {counts['survived']} survived, {counts['broken']} "
          f"broken of {len(entries)}; kill rate {counts['caught'] / len(entries):.0%}; "
          f"{time.monotonic() - start:.0f} s")
    return 0 if counts["caught"] == len(entries) else 1


if __name__ == "__main__":
    sys.exit(main())
