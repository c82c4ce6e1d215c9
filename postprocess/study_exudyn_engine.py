#!/usr/bin/env python3
"""Study: the engine of docs/scene.md in ffrf and in Exudyn on the same bodies and modes (issue 30;
docs/theory.md 4.5). For each case: write the engine case (input/engine_rc<N>.nml on the lc 8 mm
meshes, hand-set model: `num_modes` RC modes per body, step h, modal damping xi) and the modal
case of the same bodies and interfaces, run ffrf on both, then peer_exudyn_engine.py (with the
Exudyn interpreter given by --python); print one CSV of every case's rows to stdout (--csv: also
to a file).

Cases (name: crank RC set, modal damping, Exudyn integrator):
    rc2_damped          2, 0.02, generalized-alpha (rho_inf of the case, 0.8)
    rc2_undamped        2, 0,    generalized-alpha
    rc1_undamped        1, 0,    generalized-alpha
    rc2_undamped_trap   2, 0,    Exudyn's trapezoidal rule (index 2; ffrf's run is the alpha one)

    study_exudyn_engine.py --ffrf build/release/driver/ffrf --mesh-dir build/release/meshes
        --input-dir input --work build/release/study_exudyn --python venv/bin/python
        [--cases rc2_damped ...] [--t-end 2.0] [--num-modes 30] [--h 2.5e-5] [--csv out.csv]
        [-- peer options, e.g. --speed-tol 0.05]
"""
import argparse
import csv
import io
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import namelist  # noqa: E402

CASES = {
    "rc2_damped": ("engine_rc2", 0.02, "alpha"),
    "rc2_undamped": ("engine_rc2", 0.0, "alpha"),
    "rc1_undamped": ("engine_rc1", 0.0, "alpha"),
    "rc2_undamped_trap": ("engine_rc2", 0.0, "trapezoidal"),
}
FLEXIBLE = ("crank", "conrod")
MODAL_BODY_KEYS = ("name", "mesh_file", "volumes", "young", "poisson", "density")


def engine_case(source, damping, t_end, num_modes, h):
    """The engine case (namelist groups) and its modal case (text)."""
    groups = namelist.read(source)
    namelist.find(groups, "model").set("selection", "manual")
    integrator = namelist.find(groups, "integrator")
    integrator.set("h", h)
    integrator.set("t_end", t_end)
    modal = [namelist.Group("run", [("title", ["modes of the bodies of " +
                                               os.path.basename(source)])])]
    for name in FLEXIBLE:
        body = namelist.find(groups, "body", name=name)
        body.set("mesh_file", f"{name}_lc8.msh")
        body.set("num_modes", num_modes)
        body.set("modal_damping", damping)
        modal.append(namelist.Group("body", [(k, body.get_list(k)) for k in MODAL_BODY_KEYS]))
        modal.extend(namelist.find_all(groups, "interface", body=name))
    modal.append(namelist.Group("modes", [("num_modes", [num_modes])]))
    return groups, namelist.format_groups(modal)


def run(command, log):
    start = time.perf_counter()
    with open(log, "w") as out:
        status = subprocess.call(command, stdout=out, stderr=subprocess.STDOUT,
                                 env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    return status, time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ffrf", required=True)
    parser.add_argument("--mesh-dir", required=True)
    parser.add_argument("--input-dir", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--python", required=True, help="interpreter that imports exudyn")
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--t-end", type=float, default=2.0)
    parser.add_argument("--num-modes", type=int, default=30)
    parser.add_argument("--h", type=float, default=2.5e-5)
    parser.add_argument("--csv")
    parser.add_argument("--skip-code", type=int,
                        help="exit with this code when --python cannot import exudyn (ctest skip)")
    parser.add_argument("peer_options", nargs="*", help="after --: options of the peer script")
    args = parser.parse_args(argv)
    os.makedirs(args.work, exist_ok=True)
    probe = subprocess.call([args.python, "-c", "import exudyn"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL) if os.path.exists(args.python) else 1
    if probe != 0:
        print(f"study_exudyn_engine: {args.python} does not import exudyn (see exudyn_venv.py)",
              file=sys.stderr)
        return args.skip_code if args.skip_code is not None else 2
    peer = os.path.join(os.path.dirname(os.path.abspath(__file__)), "peer_exudyn_engine.py")

    header, rows, failed = None, [], []
    done = {}
    for name in args.cases:
        source, damping, solver = CASES[name]
        ffrf_name = name.replace("_trap", "")
        groups, modal_text = engine_case(os.path.join(args.input_dir, source + ".nml"), damping,
                                         args.t_end, args.num_modes, args.h)
        case_file = os.path.join(args.work, ffrf_name + ".nml")
        modal_file = os.path.join(args.work, ffrf_name + "_modes.nml")
        if ffrf_name not in done:
            with open(case_file, "w") as out:
                out.write(namelist.format_groups(groups))
            with open(modal_file, "w") as out:
                out.write(modal_text)
            for nml in (modal_file, case_file):
                status, wall = run([args.ffrf, nml, "--mesh-dir", args.mesh_dir, "--output-dir",
                                    args.work, "--quiet"], nml[:-4] + ".log")
                if status != 0:
                    sys.exit(f"study_exudyn_engine: ffrf {nml} exited {status}, see "
                             f"{nml[:-4]}.log")
                print(f"study_exudyn_engine: ffrf {os.path.basename(nml)}: {wall:.1f} s",
                      file=sys.stderr)
            done[ffrf_name] = True
        command = [args.python, "-W", "ignore", peer,
                   "--modes", os.path.join(args.work, ffrf_name + "_modes.h5"),
                   "--ffrf", os.path.join(args.work, ffrf_name + ".h5"),
                   "--solver", solver, "--label", name,
                   "--npz", os.path.join(args.work, name + "_exudyn.npz")] + args.peer_options
        start = time.perf_counter()
        result = subprocess.run(command, capture_output=True, text=True,
                                env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        print(f"study_exudyn_engine: Exudyn {name}: {time.perf_counter() - start:.1f} s",
              file=sys.stderr)
        sys.stderr.write(result.stderr)
        if result.returncode != 0:
            failed.append(name)
        table = list(csv.reader(io.StringIO(result.stdout)))
        if table:
            header = table[0]
            rows.extend(table[1:])
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    if header:
        writer.writerow(header)
    writer.writerows(rows)
    sys.stdout.write(buffer.getvalue())
    if args.csv:
        with open(args.csv, "w") as out:
            out.write(buffer.getvalue())
    if failed:
        print(f"study_exudyn_engine: peer check failed for {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
