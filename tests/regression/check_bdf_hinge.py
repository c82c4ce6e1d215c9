#!/usr/bin/env python3
"""A mechanism run on a body meshed as Nastran bulk data follows the same run on the Gmsh mesh
(issue 26: bulk data in mechanism runs, not only in modal runs).

The scene: the conrod (conrod_lc8.msh, 6 RC normal modes, big_end clamped RC set) on a revolute
joint to the ground at its big_end interface, driven by a torque of 1 N m about z, 0.05 s at
h = 1e-4 s (the hinge of tests/regression/exudyn_export.py, its namelist text taken from
there). The deck: the Gmsh mesh written by pyNastran with check_bdf_crank.write_deck (GRIDs in
large fields, half of them INCLUDEd, every 50th in free fields; CTETRA, PSOLID 1, MAT1 with the
scene's material), the interfaces big_end and small_end as RBE3 101 and 102 (uniform weights,
as the Gmsh run's default `weighting = 'uniform'`), their reference grids at the virtual nodes
of the Gmsh run (read from its results: an input of the deck, not a result compared). The same
scene on the deck (`mesh_file = 'conrod_lc8.bdf'`, `volumes = '1'`, interfaces '101' and '102',
the material from MAT1) must give the conrod's rotation angle at every step to 1e-10 rad and
its frequencies to 2e-11 relative (the same model up to the last digits of the coordinates:
large fields keep 14 to 15 significant digits; measured 1.6e-14 rad and 3.7e-12 to 5.2e-12).

    check_bdf_hinge.py --driver FFRF --mesh-dir MESH_DIR --work WORK --venv VENV

Exit 0 pass, 1 fail, 77 when pyNastran cannot be installed (check_bdf_crank.in_venv).
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import check_bdf_crank  # noqa: E402
from exudyn_export import HINGE_BODY, HINGE_SCENE, HINGE_H, HINGE_T_END, HINGE_RHO, \
    HINGE_TORQUE  # noqa: E402

# measured: angle 0.7e-14 to 1.6e-14 rad (0.27 rad at the end), frequencies 3.7e-12 to 5.2e-12
# from run to run (8.3e-12 with &modes tolerance at its default): the coordinates' last
# digits move the constrained modes of this finer mesh more than the crank's of
# check_bdf_crank (5e-13)
ANGLE_TOL, FREQUENCY_RTOL = 1e-10, 2e-11
NAMES = ("big_end", "small_end")


def angles(h5_file):
    """Time, the conrod's rotation angle about z (rad), its frequencies (Hz)."""
    import h5py
    import numpy as np
    with h5py.File(h5_file, "r") as h5:
        ep = h5["bodies/conrod/euler_parameters"][()]
        return (h5["time/t"][()], np.unwrap(2.0 * np.arctan2(ep[:, 3], ep[:, 0])),
                h5["bodies/conrod/modes/frequency"][()])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--driver", required=True)
    parser.add_argument("--mesh-dir", required=True, help="folder of conrod_lc8.msh")
    parser.add_argument("--work", required=True)
    parser.add_argument("--venv", help="run in this virtual environment (made if needed)")
    args = parser.parse_args()
    if args.venv:
        return check_bdf_crank.in_venv(args.venv, __file__)
    import h5py
    import numpy as np
    os.makedirs(args.work, exist_ok=True)
    scene = HINGE_SCENE.format(h=HINGE_H, t_end=HINGE_T_END, rho=HINGE_RHO, torque=HINGE_TORQUE)
    msh_case = os.path.join(args.work, "hinge.nml")
    with open(msh_case, "w") as f:
        f.write(scene + HINGE_BODY.format(extra=", type = 'flexible'"))
    # check_bdf_crank.run: Ritz values to machine precision (&modes tolerance = 0), so that
    # what is compared is the model, not the eigensolver's stopping point
    msh_h5 = check_bdf_crank.run(args.driver, msh_case, args.mesh_dir,
                                 os.path.join(args.work, "msh"))
    with h5py.File(msh_h5, "r") as f:
        centroids = {n: f[f"bodies/conrod/interfaces/{n}/virtual_node"][()] for n in NAMES}
    deck = os.path.join(args.work, "conrod_lc8.bdf")
    faces = check_bdf_crank.write_deck(os.path.join(args.mesh_dir, "conrod_lc8.msh"), centroids,
                                       deck, NAMES)
    print(f"deck {deck}: " + ", ".join(f"{n} {len(faces[n])} grids" for n in NAMES))
    # the same scene on the deck: its interfaces are the RBE3 elements 101 and 102, whose
    # reference grids are the virtual nodes; the material is MAT1's
    body = ("&body name = 'conrod', mesh_file = 'conrod_lc8.bdf', volumes = '1', "
            "type = 'flexible' /\n"
            "&interface body = 'conrod', name = '101', rc = 'Tx Ty Tz Rx Ry Rz' /\n"
            "&interface body = 'conrod', name = '102', rc = '' /\n&modes num_modes = 6 /\n")
    bdf_case = os.path.join(args.work, "hinge_bdf.nml")
    with open(bdf_case, "w") as f:
        f.write(scene.replace("'big_end'", "'101'") + body)
    bdf_h5 = check_bdf_crank.run(args.driver, bdf_case, args.work,
                                 os.path.join(args.work, "bdf"))
    t_a, angle_a, f_a = angles(msh_h5)
    t_b, angle_b, f_b = angles(bdf_h5)
    if not np.array_equal(t_a, t_b):
        sys.exit(f"check_bdf_hinge: {len(t_b)} steps on the deck, {len(t_a)} on the Gmsh mesh")
    angle_error = float(np.abs(angle_b - angle_a).max())
    frequency_error = float(np.abs(f_b / f_a - 1.0).max())
    print(f"hinge: {len(t_a) - 1} steps to {t_a[-1]:.3f} s, angle at the end {angle_a[-1]:.9f} "
          f"rad (Gmsh) {angle_b[-1]:.9f} rad (deck); max |difference| {angle_error:.2e} rad "
          f"(tolerance {ANGLE_TOL:g}); frequencies {f_a[0]:.4f} .. {f_a[-1]:.4f} Hz, max rel. "
          f"difference {frequency_error:.2e} (tolerance {FREQUENCY_RTOL:g})")
    failed = not angle_error <= ANGLE_TOL or not frequency_error <= FREQUENCY_RTOL
    if failed:
        print("check_bdf_hinge: FAIL: the deck's run differs from the Gmsh mesh's",
              file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
