#!/usr/bin/env python3
"""Extrapolate the modal solve of the crank to more dofs and more ranks, from MUMPS's own
analysis estimates and the benchmark measured on this machine. Not a test: a model, printed as a
Markdown table with its assumptions.

Input 1 (--estimates): CSV with one row per mesh, columns
    lc_mm, dofs, factor_entries, flops, memory_mb
from the MUMPS analysis (INFOG(20) entries in the factors, RINFOG(1) elimination flops,
INFOG(17) total in-core memory in MB).
Input 2 (--measured): the CSV of postprocess/benchmark_modes.py (one row per lc and rank
count) with at least dofs, ranks, factorisation_s, eigen_loop_s, ffrf_total_s,
peak_memory_mib (the largest rank's peak), factor_entries.

The model (printed with the table):
  * factor entries and flops follow power laws in the dofs, fitted on the estimates
    (nested dissection on a 3D mesh predicts entries ~ n^(4/3), flops ~ n^2);
  * the factorisation runs at the flop rate per core measured on one rank, times a parallel
    efficiency e(p) = e2^log2(p), e2 the measured 2-rank efficiency of the factorisation
    (e2 = 1 is not assumed);
  * the solves (about 40 per modal run: 12 modes, 24-vector Lanczos basis) cost a fixed time per
    factor entry, measured on one rank, divided by p e(p);
  * the memory per rank is the MUMPS in-core estimate divided by p times the imbalance
    measured with 2 ranks (largest rank over mean), plus a replicated part per dof (mesh,
    K, M, Lanczos vectors, measured as the peak not explained by MUMPS).
"""
import argparse
import csv
import math
import sys


def read_rows(path):
    with open(path) as f:
        return [{k: float(v) for k, v in row.items() if v not in ("", None) and
                 k is not None and _is_number(v)} for row in csv.DictReader(f)]


def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def power_fit(x, y):
    """Least-squares fit of log y = log c + a log x; returns (c, a)."""
    lx = [math.log(v) for v in x]
    ly = [math.log(v) for v in y]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    sxy = sum((a - mx) * (b - my) for a, b in zip(lx, ly))
    slope = sxy / sxx
    return math.exp(my - slope * mx), slope


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--estimates", required=True, help="MUMPS analysis estimates (CSV)")
    parser.add_argument("--measured", required=True, help="benchmark_modes.py CSV")
    parser.add_argument("--dofs", default="1e6,2.2e6,5e6,1e7", help="dofs to extrapolate to")
    parser.add_argument("--ranks", default="1,2,8,16,32,64", help="rank counts")
    parser.add_argument("--solves", type=float, default=40.0,
                        help="solves per modal run (12 modes: about 40)")
    args = parser.parse_args()

    est = sorted(read_rows(args.estimates), key=lambda r: r["dofs"])
    if len(est) < 2:
        sys.exit("scaling_table: need estimates on at least two meshes")
    c_fac, a_fac = power_fit([r["dofs"] for r in est], [r["factor_entries"] for r in est])
    c_flop, a_flop = power_fit([r["dofs"] for r in est], [r["flops"] for r in est])
    c_mem, a_mem = power_fit([r["dofs"] for r in est], [r["memory_mb"] for r in est])

    meas = read_rows(args.measured)
    one = [r for r in meas if r.get("ranks", 1) == 1 and r.get("factorisation_s", 0) > 0]
    two = [r for r in meas if r.get("ranks", 1) == 2 and r.get("factorisation_s", 0) > 0]
    if not one:
        sys.exit("scaling_table: need a one-rank measurement")
    ref = max(one, key=lambda r: r["dofs"])
    flop_rate = (c_flop * ref["dofs"] ** a_flop) / ref["factorisation_s"]
    solve_per_entry = ref["eigen_loop_s"] / (args.solves * ref["factor_entries"])
    other_s_per_dof = max(ref["ffrf_total_s"] - ref["factorisation_s"] - ref["eigen_loop_s"],
                          0.0) / ref["dofs"]
    mumps_mb_ref = c_mem * ref["dofs"] ** a_mem
    replicated_mb_per_dof = max(ref["peak_memory_mib"] * 1.048576 - mumps_mb_ref, 0.0) / \
        ref["dofs"]
    e2, imbalance = 1.0, 1.0
    same = [r for r in two if abs(r["dofs"] - ref["dofs"]) / ref["dofs"] < 1e-6]
    if same:
        r2 = same[0]
        e2 = ref["factorisation_s"] / (2.0 * r2["factorisation_s"])
        share_mb = mumps_mb_ref / 2.0 + replicated_mb_per_dof * ref["dofs"]
        imbalance = max(r2["peak_memory_mib"] * 1.048576 / share_mb, 1.0)

    def efficiency(p):
        return e2 ** math.log2(p) if p > 1 else 1.0

    print("| dofs | ranks | factor entries | flops | factorisation s | solves s | "
          "total s | memory per rank GB |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n in [float(x) for x in args.dofs.split(",")]:
        entries = c_fac * n ** a_fac
        flops = c_flop * n ** a_flop
        mumps_mb = c_mem * n ** a_mem
        for p in [int(x) for x in args.ranks.split(",")]:
            speed = p * efficiency(p)
            fac_s = flops / flop_rate / speed
            sol_s = args.solves * entries * solve_per_entry / speed
            total = fac_s + sol_s + other_s_per_dof * n
            mem_gb = (mumps_mb / p * (imbalance if p > 1 else 1.0) +
                      replicated_mb_per_dof * n) / 1000.0
            print(f"| {n:.3g} | {p} | {entries:.3g} | {flops:.3g} | {fac_s:.0f} | "
                  f"{sol_s:.0f} | {total:.0f} | {mem_gb:.1f} |")
    print()
    mesh_list = ", ".join(f"{r['dofs']:.0f}" for r in est)
    print(f"Fitted on {len(est)} meshes ({mesh_list} dofs): "
          f"factor entries ~ n^{a_fac:.2f}, flops ~ n^{a_flop:.2f}, MUMPS memory ~ "
          f"n^{a_mem:.2f}. One-rank reference {ref['dofs']:.0f} dofs: "
          f"{flop_rate / 1e9:.2f} GFlop/s in the factorisation, "
          f"{solve_per_entry * 1e9:.2f} ns per factor entry per solve, "
          f"{replicated_mb_per_dof * 1e3:.2f} kB per dof outside MUMPS. Two-rank "
          f"factorisation efficiency e2 = {e2:.2f} (e(p) = e2^log2 p), memory imbalance "
          f"{imbalance:.2f}.")


if __name__ == "__main__":
    main()
