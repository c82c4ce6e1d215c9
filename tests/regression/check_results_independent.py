#!/usr/bin/env python3
"""Every dataset of an ffrf results file checked against a computation independent of ffrf's
Fortran (issue 28 item 3): the body's stiffness K and consistent mass M are assembled again in
numpy (postprocess/peer_tet10.py, Tet10 in Gmsh's node order, docs/method.md "Method and
conventions") from the file's own mesh (modal files) or from the mesh file of the input echo
(mechanism files, --mesh-dir), with the material of /input/namelist.

    check_results_independent.py RESULTS [--mesh-dir DIR] [--kind modal|craig_bampton|mechanism]
                                 [--reused] [--restarted] [--skip-missing]

M is assembled twice: integrated exactly (peer_tet10) and with ffrf's 14-point degree-5 rule
(written here, checked by its moments); on curved Tet10 they differ by the rule's error, so the
identities (mass normalisation, eigen residuals, kinetic energy) use the latter and the exact one
bounds that error.

Modal files, every body: the assembly itself (K times the six rigid motions vanishes, 1^T M 1 =
rho V with V integrated here); /modes/shape mass-normalised (Psi M Psi^T = I) and K-orthogonal
with Psi K Psi^T = diag((2 pi f)^2) of /modes/frequency; the reduced eigenproblem (Psi K Psi^T,
Psi M Psi^T) against the frequencies; each mode's residual ||P (K psi - w^2 M psi)|| / ||P K psi||
on the RC-constrained space (P onto null(C), C = D G for RBE3, the rigid spider for RBE2) against
the 1e-8 of the house style and against /modes/residual; /modes/virtual_node_shape recomputed from
the interface nodes' rows of the shapes (RBE3: Nastran's weighted rigid fit G = (S^T W S)^-1 S^T W
with the file's weights; RBE2: least-squares rigid fit, exact: the face follows it); the RC rows
of the virtual-node shapes zero; /mass/{mass, center_of_mass, inertia} from M; the Sturm count
identity; /interfaces/<name>/{mpc, rc_dofs, weights} against the echo and, with --mesh-dir, the
nodes, area and area centroid (the virtual node) from the mesh file's Tri6 faces. Craig-Bampton (basis attribute): the same, and the basis split back into its parts:
the combinations of the modes with every virtual node held are the fixed-interface modes (their
Rayleigh-Ritz values against /modes/fixed_interface_frequency, their residuals on the
fixed-interface space with the independent K and M), the K-orthogonal complement holds the
static constraint modes (K x has no component on the free space: least strain energy for given
virtual-node motions), and their counts against /modes/num_static_modes.

Mechanism files (engine runs, restarted and reused-mode runs): for every flexible body the
shapes and virtual-node shapes as above (the interface nodes from the mesh file's physical
surfaces); per step the strain energy sum_b 1/2 zeta^T (Psi K Psi^T) zeta against /energy/strain;
the kinetic energy at the end from /final_state/{q, v} (rigid bodies from their input mass, centre
of mass and inertia; flexible bodies 1/2 v^T M v with the nodal velocities rebuilt from R, the
Euler parameters and zeta, docs/theory.md 3.1); /final_state against the last recorded step; the
balance D = W - (T + U - T0 - U0) - D_p of the stored series; the main bearings' virtual nodes of
the crank on their ground points and the crank pin / piston pin / cylinder joints closed at every
step (R + A (x_V + Psi_V zeta)); the crank angle against 2 atan2(e3, e0) of the crank and the
crank speed against e_z . G(theta) theta_dot at the end; the joint reactions' action and reaction;
each rigid body's momentum and angular momentum (planar about z) at the end against the impulse
of the stored reactions, pressure load and gravity (a run from rest). Invariants (docs/theory.md 3.2) are not
stored in results files, so there is nothing of them to check.

Not checked by value: /energy/{external_work, scheme_dissipation, damping_dissipation} beyond the
balance identity (and D_p non-decreasing)
(the rates per step are not stored), /time/pressure (the pressure model), reaction_min_norm,
counters, timings, solver statistics, fingerprints.

Tolerances: each check states its reason and the value measured beside it (tests/TOLERANCES.md,
"results_independent_*"). Any failure exits 1 after all checks ran.
"""
import argparse
import os
import sys
import time

import h5py
import numpy as np
import scipy.linalg as la

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', '..', 'postprocess'))
import namelist  # noqa: E402
import peer_tet10  # noqa: E402

FAILURES = []
REPORT = True           # print each check (results_independent_faults.py turns it off)
_ASSEMBLED = {}
DOFS = ('Tx', 'Ty', 'Tz', 'Rx', 'Ry', 'Rz')


def check(condition, what):
    if REPORT:
        print(('ok     ' if condition else 'FAILED ') + what, flush=True)
    if not condition:
        FAILURES.append(what)


def check_le(what, value, bound, note=''):
    """value <= bound (NaN fails)."""
    check(bool(value <= bound), f'{what}: {value:.3g} <= {bound:.3g}' + (f' ({note})' if note else ''))


def text(value):
    value = value[()] if isinstance(value, h5py.Dataset) else value
    if isinstance(value, np.ndarray):
        value = value.item() if value.shape == () else value[0]
    return value.decode().strip() if isinstance(value, bytes) else str(value).strip()


def skew(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def euler_rotation(e):
    """A(theta) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~) (docs/theory.md 3.1)."""
    e0, v = e[0], np.asarray(e[1:])
    return (2 * e0 ** 2 - 1) * np.eye(3) + 2 * (np.outer(v, v) + e0 * skew(v))


def euler_g_bar(e):
    """G_bar = 2 [-e, e0 I - e~]: omega_bar = G_bar theta_dot (body frame, theory.md 3.1)."""
    e0, v = e[0], np.asarray(e[1:])
    return 2 * np.column_stack([-v, e0 * np.eye(3) - skew(v)])


def rc_dofs(value):
    words = value.replace(',', ' ').split()
    out = []
    for w in words:
        if w.isdigit():
            out += [DOFS[int(c) - 1] for c in w]
        else:
            out.append(w)
    return out


# ------------------------------------------------------------------------------ meshes

def read_msh41(path, volumes, surfaces):
    """Gmsh MSH 4.1 ASCII: node tags and coordinates, the Tet10 (type 11) of the physical volumes
    `volumes`, the Tri6 (type 9) node tags of each physical surface in `surfaces`."""
    with open(path) as f:
        lines = f.read().split('\n')
    sec = {}
    i = 0
    while i < len(lines):
        if lines[i].startswith('$') and not lines[i].startswith('$End'):
            name = lines[i][1:]
            j = lines.index('$End' + name, i)
            sec[name] = lines[i + 1:j]
            i = j
        i += 1
    if not sec['MeshFormat'][0].startswith('4.1 0'):
        raise SystemExit(f'{path}: only MSH 4.1 ASCII is read here')
    names = {}
    for line in sec['PhysicalNames'][1:]:
        d, tag, name = line.split(maxsplit=2)
        names[(int(d), int(tag))] = name.strip('"')
    ent = sec['Entities']
    counts = [int(x) for x in ent[0].split()]
    phys = {}
    row = 1
    for dim in range(4):
        for _ in range(counts[dim]):
            w = ent[row].split()
            row += 1
            tag = int(w[0])
            k = 4 if dim == 0 else 7
            nphys = int(w[k])
            phys[(dim, tag)] = [names[(dim, int(p))] for p in w[k + 1:k + 1 + nphys]]
    nodes = sec['Nodes']
    nblocks = int(nodes[0].split()[0])
    row = 1
    tags, xyz = [], []
    for _ in range(nblocks):
        w = nodes[row].split()
        row += 1
        n = int(w[3])
        tags += [int(x) for x in nodes[row:row + n]]
        xyz += [[float(x) for x in line.split()[:3]] for line in nodes[row + n:row + 2 * n]]
        row += 2 * n
    tets, faces = [], {s: [] for s in surfaces}
    elements = sec['Elements']
    nblocks = int(elements[0].split()[0])
    row = 1
    for _ in range(nblocks):
        dim, tag, etype, n = (int(x) for x in elements[row].split())
        row += 1
        block = [[int(x) for x in line.split()[1:]] for line in elements[row:row + n]]
        row += n
        groups = phys.get((dim, tag), [])
        if etype == 11 and any(g in volumes for g in groups):
            tets += block
        if etype == 9:
            for g in groups:
                if g in faces:
                    faces[g] += block
    return np.array(tags), np.array(xyz), np.array(tets), {k: np.array(v) for k, v in faces.items()}


class Body:
    """A flexible body of a results file: mesh (0-based Tet10), K, M, shapes, interfaces."""

    def __init__(self, h5, name, groups, mesh_dir):
        self.name = name
        g = h5['bodies/' + name]
        echo = namelist.find(groups, 'body', name=name)
        self.young, self.poisson, self.density = (float(echo.get(k)) for k in
                                                  ('young', 'poisson', 'density'))
        self.order = [text(s) for s in g['interfaces/order'][()]]
        specs = {text(i.get('name')): i for i in namelist.find_all(groups, 'interface', body=name)}
        if 'mesh' in g:
            self.xyz = g['mesh/coordinates'][()]
            self.tets = g['mesh/tets'][()] - 1
            self.nodes = {k: g[f'interfaces/{k}/nodes'][()] - 1 for k in self.order}
            self.weights = {k: g[f'interfaces/{k}/weights'][()] for k in self.order}
            self.source = 'the file\'s /mesh'
        else:
            if mesh_dir is None:
                raise SystemExit(f'body {name}: no /mesh in the file, give --mesh-dir')
            path = os.path.join(mesh_dir, text(echo.get('mesh_file')))
            vols = echo.get('volumes')
            vols = vols if isinstance(vols, list) else vols.split()
            tags, xyz, tets, faces = read_msh41(path, vols, self.order)
            used = np.unique(tets)
            index = np.full(tags.max() + 1, -1)
            index[tags] = np.arange(len(tags))
            # the body's nodes: those of its tetrahedra, in ascending tag order
            self.xyz = xyz[index[used]]
            local = np.full(tags.max() + 1, -1)
            local[used] = np.arange(len(used))
            self.tets = local[tets]
            self.nodes = {k: local[np.unique(faces[k])] for k in self.order}
            self.weights = {}
            for k in self.order:
                weighting = text(specs[k].get('weighting', 'uniform'))
                if weighting != 'uniform':
                    raise SystemExit(f'{name}/{k}: weighting {weighting} needs the weights, which '
                                     'a mechanism file does not store; only uniform is checked')
                self.weights[k] = np.ones(len(self.nodes[k]))
            self.source = os.path.basename(path)
            self.faces = {k: local[faces[k]] for k in self.order}
        if 'mesh' in g:
            self.faces = None
            if mesh_dir is not None:
                # the faces of the interfaces from the mesh file, numbered by /mesh/node_tags
                path = os.path.join(mesh_dir, text(echo.get('mesh_file')))
                vols = echo.get('volumes')
                vols = vols if isinstance(vols, list) else vols.split()
                tags, _, _, faces = read_msh41(path, vols, self.order)
                node_tags = g['mesh/node_tags'][()]
                local = np.full(max(tags.max(), node_tags.max()) + 1, -1)
                local[node_tags] = np.arange(len(node_tags))
                self.faces = {k: local[faces[k]] for k in self.order}
        self.specs = specs
        self.mpc = {k: text(specs[k].get('mpc', 'RBE3')).upper() for k in self.order}
        self.rc = {k: rc_dofs(text(specs[k].get('rc', ''))) for k in self.order}
        self.vn = {k: g[f'interfaces/{k}/virtual_node'][()] for k in self.order}
        self.freq = g['modes/frequency'][()]
        self.shape = g['modes/shape'][()]                         # (m, 3n)
        self.vshape = g['modes/virtual_node_shape'][()]           # (m, 6 n_if)
        self.basis = text(g['modes'].attrs.get('basis', b'rc_normal'))
        self.group = g
        t0 = time.time()
        key = (self.xyz.tobytes(), self.tets.tobytes(), self.young, self.poisson, self.density)
        if key not in _ASSEMBLED:       # one process checking several files of one mesh
            _ASSEMBLED[key] = (*peer_tet10.assemble(self.xyz, self.tets, self.young,
                                                    self.poisson, self.density),
                               scalar_mass_14(self.xyz, self.tets, self.density))
        self.K, self.M, self.Ms14 = _ASSEMBLED[key]
        if REPORT:
            print(f'[{name}] {len(self.xyz)} nodes, {len(self.tets)} Tet10 from {self.source}: '
                  f'K, M assembled in {time.time() - t0:.1f} s', flush=True)

    # -------------------------------------------------------------- the assembly itself
    def check_assembly(self):
        x = self.xyz
        n = len(x)
        rigid = np.zeros((3 * n, 6))
        for i in range(3):
            rigid[i::3, i] = 1.0
        c = x - x.mean(axis=0)
        for i in range(3):
            e = np.eye(3)[i]
            rigid[:, 3 + i] = np.cross(e, c).ravel()
        kr = self.K @ rigid
        scale = abs(self.K).max() * np.abs(rigid).max(axis=0) * 30
        # identity, round-off of sums of ~30 terms of size |K|: measured 1e-15 .. 3e-15
        check_le(f'[{self.name}] K times the six rigid motions / (30 max|K| |r|)',
                 float((np.abs(kr).max(axis=0) / scale).max()), 1e-14, 'round-off, measured 2.0e-17')
        volume = tet10_volume(x, self.tets)
        mass = float(self.M[0::3, 0::3].sum())
        # 1^T M 1 = rho int det J: two quadratures of the same polynomial, both exact
        check_le(f'[{self.name}] 1^T M_x 1 against rho V (V by a degree-5 rule here), relative',
                 abs(mass / (self.density * volume) - 1), 1e-14, 'round-off, measured 3.3e-16')
        self.mass_total = mass

    # -------------------------------------------------------------- interfaces
    def check_interfaces(self):
        """/interfaces/<name>/{mpc, rc_dofs, weights, nodes, area, virtual_node} against the echo
        and, with the mesh file's Tri6 faces, the face nodes, the area int dA and the area
        centroid int x dA / A (an 8 x 8 collapsed Gauss rule on each curved Tri6)."""
        g = self.group
        for k in self.order:
            f = g['interfaces/' + k]
            spec = self.specs[k]
            if 'mpc' in f:
                check(text(f['mpc']).upper() == self.mpc[k] and
                      rc_dofs(text(f['rc_dofs'])) == self.rc[k],
                      f'[{self.name}] {k}: /mpc {text(f["mpc"])} and /rc_dofs '
                      f'{text(f["rc_dofs"])!r} as in the echo')
            if 'weights' in f and text(spec.get('weighting', 'uniform')) == 'uniform':
                check(bool(np.all(f['weights'][()] == 1.0)), f'[{self.name}] {k}: uniform '
                      'weights all 1')
            if self.faces is None:
                continue
            tri = self.faces[k]
            if 'nodes' in f:
                check(bool(np.all(tri >= 0)) and np.array_equal(np.unique(tri),
                                                                np.sort(self.nodes[k])),
                      f'[{self.name}] {k}: /nodes are the {len(self.nodes[k])} nodes of the '
                      f'physical surface\'s {len(tri)} Tri6 in the mesh file')
            area, centroid = tri6_area_centroid(self.xyz, tri)
            if 'area' in f:
                        check_le(f'[{self.name}] {k}: /area against int dA of the Tri6 faces, relative',
                         abs(float(np.ravel(f['area'][()])[0]) / area - 1), 1e-7,
                         'ffrf\'s 7-point degree-5 rule on curved Tri6 against a converged 64-point '
                         'rule (8 and 16 points agree to all digits), measured 1.8e-8 .. 2.6e-8')
            if text(spec.get('virtual_node', 'centroid')) == 'centroid':
                check_le(f'[{self.name}] {k}: /virtual_node against the area centroid '
                         'int x dA / A, / face size', float(np.abs(self.vn[k] - centroid).max()
                                                            / np.sqrt(area)), 1e-8,
                         'as the area: the 7-point rule, measured 1.5e-9 .. 2.4e-9')
            else:
                check(np.array_equal(self.vn[k], np.array(spec.get('position'), float)),
                      f'[{self.name}] {k}: /virtual_node equals the echo\'s position')

    def rows(self):
        """Per interface: 0-based node numbers, and the RBE3 fit G (6 x 3 nB) or RBE2 F."""
        out = {}
        for k in self.order:
            nodes = self.nodes[k]
            r = self.xyz[nodes] - self.vn[k]
            S = np.zeros((3 * len(nodes), 6))
            for i, ri in enumerate(r):
                S[3 * i:3 * i + 3, :3] = np.eye(3)
                S[3 * i:3 * i + 3, 3:] = -skew(ri)
            out[k] = (nodes, S)
        return out

    def vn_fit(self, S, w, qb):
        """q_V of interface motions qb (3 nB, m): RBE3 weighted fit (S^T W S)^-1 S^T W qb; with
        w = 1 it is also the RBE2 least-squares fit F^+ qb."""
        W = np.repeat(w, 3)
        return np.linalg.solve(S.T @ (W[:, None] * S), S.T @ (W[:, None] * qb))

    def check_virtual_nodes(self, psi, vshape, label):
        """vshape (m, 6 n_if) against the fits of the interface rows of psi (m, 3n)."""
        rows = self.rows()
        worst = 0.0
        worst_rc = 0.0
        worst_rbe2 = 0.0
        scale = np.abs(vshape[:, :]).max()
        computed = np.zeros_like(vshape)
        for j, k in enumerate(self.order):
            nodes, S = rows[k]
            dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
            qb = psi[:, dofs].T
            w = self.weights[k] if self.mpc[k] == 'RBE3' else np.ones(len(nodes))
            qv = self.vn_fit(S, w, qb)                       # (6, m)
            computed[:, 6 * j:6 * j + 6] = qv.T
            # scale each block: translations in m kg^-1/2, rotations in rad kg^-1/2
            worst = max(worst, np.abs(qv.T - vshape[:, 6 * j:6 * j + 6]).max() / scale)
            for d in self.rc[k]:
                worst_rc = max(worst_rc, np.abs(qv[DOFS.index(d)]).max() / scale,
                               np.abs(vshape[:, 6 * j + DOFS.index(d)]).max() / scale)
            if self.mpc[k] == 'RBE2':
                worst_rbe2 = max(worst_rbe2, np.abs(S @ qv - qb).max() / np.abs(qb).max())
        # linear solves of 6 x 6 normal matrices of well-spread faces: round-off
        check_le(f'[{self.name}] {label}: /virtual_node_shape against the fit of the interface '
                 'rows of the shapes, / max|Psi_V|', worst, 1e-13,
                 'round-off of 6 x 6 fits (normal matrix condition ~1e4), measured <= 3.3e-15')
        check_le(f'[{self.name}] {label}: RC rows of the virtual-node shapes (computed and '
                 'stored), / max|Psi_V|', worst_rc, 1e-13,
                 'zero up to the constrained solve\'s round-off, measured <= 1.4e-16')
        if any(self.mpc[k] == 'RBE2' for k in self.order):
            check_le(f'[{self.name}] {label}: RBE2 faces follow their virtual node rigidly, '
                     'max|F q_V - q_B| / max|q_B|', worst_rbe2, 1e-13, 'round-off, measured 1.8e-15')
        return computed

    # -------------------------------------------------------------- modes
    def check_modes(self, label):
        psi = self.shape
        m = len(psi)
        w2 = (2 * np.pi * self.freq) ** 2
        KP = (self.K @ psi.T)                      # (3n, m)
        MP = (self.M @ psi.T)
        kk = psi @ KP
        mm = psi @ MP
        # ffrf integrates M with a 14-point degree-5 rule, peer_tet10 exactly (125 points): on
        # the curved Tet10 of the meshes they differ by ~1e-11 relative (measured 3.9e-11 on the
        # lc 8 mm crank); K uses the same 4-point rule in both, so its products agree to round-off
        err_m = np.abs(mm - np.eye(m)).max()
        check_le(f'[{self.name}] {label}: max|Psi M Psi^T - I| (M integrated exactly)', err_m,
                 1e-8, 'the 14-point rule\'s error on curved Tet10, growing with the modes\' wave '
                 'number: measured 3.9e-11 crank 8 modes, 2.3e-10 conrod, 1.1e-9 crank CB to 44 kHz')
        err_kd = np.abs(np.diag(kk) / w2 - 1).max()
        check_le(f'[{self.name}] {label}: Rayleigh quotients psi K psi^T against (2 pi f)^2, '
                 'relative', err_kd, 5e-12, 'assembly round-off, measured 4.2e-13')
        err_ko = np.abs(kk - np.diag(np.diag(kk))).max() / w2.max()
        check_le(f'[{self.name}] {label}: K-orthogonality, max off-diagonal / max w^2', err_ko,
                 2e-13, 'round-off, measured 1.6e-14')
        MP = apply_scalar(self.Ms14, psi.T)
        mm = psi @ MP
        err_m = np.abs(mm - np.eye(m)).max()
        check_le(f'[{self.name}] {label}: max|Psi M14 Psi^T - I| (M with ffrf\'s 14-point rule, '
                 'assembled here)', err_m, 1e-13, 'round-off, measured <= 4.8e-15')
        ev = la.eigh(0.5 * (kk + kk.T), 0.5 * (mm + mm.T), eigvals_only=True)
        err_ev = np.abs(ev / np.sort(w2) - 1).max()
        check_le(f'[{self.name}] {label}: eigenvalues of (Psi K Psi^T, Psi M14 Psi^T) against '
                 '(2 pi f)^2, relative', err_ev, 1e-11, 'round-off, measured <= 8.1e-13')
        check(bool(np.all(np.diff(self.freq) >= 0) and self.freq[0] > 0),
              f'[{self.name}] {label}: frequencies positive and ascending '
              f'({self.freq[0]:.2f} .. {self.freq[-1]:.2f} Hz)')
        return KP, MP, w2

    def rc_projector(self):
        """(keep, C): the residual of a mode on the RC-constrained space is the part of r on the
        dofs `keep` (all but RBE2 faces) orthogonal to the rows C (RBE3: D G, the RC rows of the
        fits), plus (F N_D)^T r_B for each RBE2 face."""
        rows = self.rows()
        n3 = 3 * len(self.xyz)
        keep = np.ones(n3, bool)
        C = []
        rbe2 = []
        for k in self.order:
            nodes, S = rows[k]
            dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
            if self.mpc[k] == 'RBE2':
                keep[dofs] = False
                free = [i for i in range(6) if DOFS[i] not in self.rc[k]]
                rbe2.append((dofs, S[:, free]))
            else:
                W = np.repeat(self.weights[k], 3)
                G = np.linalg.solve(S.T @ (W[:, None] * S), (W[:, None] * S).T)
                for d in self.rc[k]:
                    row = np.zeros(n3)
                    row[dofs] = G[DOFS.index(d)]
                    C.append(row)
        return keep, (np.array(C) if C else np.zeros((0, n3))), rbe2

    def reduced_residual(self, R, keep, C, rbe2):
        """Columns of R (3n, m) reduced to the constrained space (rc_projector)."""
        out = []
        Rk = R * keep[:, None]
        if len(C):
            Q, _ = np.linalg.qr(C.T)
            Rk = Rk - Q @ (Q.T @ Rk)
        out.append(Rk)
        for dofs, F in rbe2:
            out.append(F.T @ R[dofs])
        return np.vstack(out)

    def check_residuals(self, KP, MP, w2, label, ritz=False):
        """||P (K psi - w^2 M psi)|| / ||P K psi|| per mode on the RC-constrained space. For
        normal modes a solver accuracy (<= 1e-8); for a Craig-Bampton basis the distance of each
        Ritz vector from a normal mode (not small), compared with /modes/residual only."""
        keep, C, rbe2 = self.rc_projector()
        r = self.reduced_residual(KP - MP * w2, keep, C, rbe2)
        k = self.reduced_residual(KP, keep, C, rbe2)
        res = np.linalg.norm(r, axis=0) / np.linalg.norm(k, axis=0)
        stored = self.group['modes/residual'][()] if 'residual' in self.group['modes'] else None
        if not ritz:
            check_le(f'[{self.name}] {label}: eigen residual ||P (K psi - w^2 M psi)|| / ||P K psi|| '
                     'with the independent K, M (worst mode)', float(res.max()), 1e-8,
                     'house style for eigenpairs, measured 1.8e-10')
            if stored is not None:
                check_le(f'[{self.name}] {label}: /modes/residual against the residuals computed '
                         'here, max absolute difference', float(np.abs(res - stored).max()), 4e-11,
                         'the residuals\' own round-off floor (~1e-11 of ||K psi||), measured '
                         '3.8e-12 on values 2e-12 .. 1.8e-10')
                check_le(f'[{self.name}] {label}: /modes/residual (ffrf\'s own) against the same '
                         'bound', float(stored.max()), 1e-8, 'house style')
        elif stored is not None:
            check_le(f'[{self.name}] {label}: /modes/residual (Ritz vectors against normal modes) '
                     'against the residuals computed here, relative', float(np.abs(res / stored
                                                                                 - 1).max()),
                     5e-12, 'residuals of 1e-3 .. 1 computed from the same K, M to round-off, '
                     'measured 5e-13')

    def check_mass_properties(self):
        m, chi, J = peer_tet10.rigid_inertia(self.xyz, self.M)
        g = self.group
        if 'mass' not in g:
            return
        size = np.ptp(self.xyz, axis=0).max()
        check_le(f'[{self.name}] /mass/mass against 1^T M 1, relative',
                 abs(float(g['mass/mass'][()]) / m - 1), 2.4e-13, 'round-off, measured 2.4e-14')
        check_le(f'[{self.name}] /mass/center_of_mass against chi from M, / body size',
                 float(np.abs(g['mass/center_of_mass'][()] - chi).max() / size), 5e-14,
                 'round-off, measured 6e-15')
        check_le(f'[{self.name}] /mass/inertia against int rho (|r|^2 I - r r^T) from M, / max|J|',
                 float(np.abs(g['mass/inertia'][()] - J).max() / np.abs(J).max()), 3e-11,
                 'M quadrature and round-off, measured 3.4e-12')

    def check_craig_bampton(self, KP, MP, w2, computed_vshape):
        g = self.group['modes']
        m = len(self.freq)
        n_if = len(self.order)
        # every virtual-node dof held: the modes' combinations with zero virtual-node motion
        u, s, vt = np.linalg.svd(computed_vshape.T, full_matrices=True)   # (6 n_if, m)
        tol = 1e-9 * s[0]
        rank = int((s > tol).sum())
        num_static = int(np.ravel(g['num_static_modes'][()])[0]) if 'num_static_modes' in g \
            else int(g.attrs['num_static_modes'])
        num_rc = sum(len(self.rc[k]) for k in self.order)
        check(rank == num_static == 6 * n_if - num_rc,
              f'[{self.name}] CB: rank of the virtual-node shapes {rank} = /num_static_modes '
              f'{num_static} = 6 n_if - n_RC = {6 * n_if - num_rc} (singular values '
              f'{s[rank - 1]:.3g} > 1e-9 s_max > {s[rank] if rank < len(s) else 0:.3g})')
        N = vt[rank:].T                                    # (m, m - rank), orthonormal
        lam = np.diag(w2)
        fixed = la.eigh(N.T @ lam @ N, eigvals_only=True)
        stored = g['fixed_interface_frequency'][()]
        check(len(stored) == m - rank, f'[{self.name}] CB: {len(stored)} fixed-interface '
              f'frequencies stored, {m - rank} modes with every virtual node held')
        if len(stored) == m - rank:
            err = np.abs(np.sqrt(fixed) / (2 * np.pi) / stored - 1).max()
            # Rayleigh-Ritz of diag(w^2) on the null space: round-off of the Ritz values and of
            # the SVD's null space (its error times the gap to the static part)
            check_le(f'[{self.name}] CB: /fixed_interface_frequency against the Rayleigh-Ritz '
                     'values of the held-interface combinations, relative', err, 1e-12,
                     'eigen round-off of a 20 x 20 problem, measured 1.0e-14')
        # residuals with the independent K, M on the held space: r orthogonal to null(C_V)
        _, vecs = la.eigh(N.T @ lam @ N)
        coef = N @ vecs                                   # (m, nf)
        rows = self.rows()
        n3 = 3 * len(self.xyz)
        keep = np.ones(n3, bool)
        C = []
        for k in self.order:
            nodes, S = rows[k]
            dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
            if self.mpc[k] == 'RBE2':
                keep[dofs] = False
            else:
                W = np.repeat(self.weights[k], 3)
                G = np.linalg.solve(S.T @ (W[:, None] * S), (W[:, None] * S).T)
                for i in range(6):
                    row = np.zeros(n3)
                    row[dofs] = G[i]
                    C.append(row)
        C = np.array(C) if C else np.zeros((0, n3))
        kx = KP @ coef
        mx = MP @ coef
        lam_f = (2 * np.pi * stored) ** 2 if len(stored) == coef.shape[1] else np.diag(coef.T @ lam @ coef)
        r = self.reduced_residual(kx - mx * lam_f, keep, C, [])
        kr = self.reduced_residual(kx, keep, C, [])
        res = np.linalg.norm(r, axis=0) / np.linalg.norm(kr, axis=0)
        check_le(f'[{self.name}] CB: fixed-interface eigen residuals with the independent K, M '
                 '(every virtual node held)', float(res.max()), 1e-8,
                 'house style for eigenpairs, measured 3.5e-10')
        # static part: the K-orthogonal complement of the held space within the basis
        S_coef = la.null_space(N.T @ lam)                  # (m, num_static)
        xs = KP @ S_coef
        r = self.reduced_residual(xs, keep, C, [])
        res = np.linalg.norm(r, axis=0) / np.linalg.norm(xs, axis=0)
        check_le(f'[{self.name}] CB: static constraint modes: K x on the held space / ||K x|| '
                 '(least strain energy for their virtual-node motions)', float(res.max()), 4e-12,
                 'static solves with MUMPS factors: round-off times the condition of K, measured 3.6e-13')


def tet14_rule():
    """Walkington's (2000) 14-point degree-5 rule on the unit tetrahedron (volume 1/6): two s31
    orbits and one s22 orbit, the rule ffrf's mass matrix uses (docs/method.md "Method and
    conventions"). Parameters from the literature; checked here by its moments, every monomial of
    degree <= 5 against a! b! c! / (a + b + c + 3)!, so a wrong digit fails before anything else."""
    import itertools
    import math
    pts, wts = [], []
    for a, w in ((0.3108859192633006097973457, 0.01878132095300264179986428),
                 (0.09273525031089122640232391, 0.01224884051939365825728503)):
        for k in range(4):
            lam = [a] * 4
            lam[k] = 1 - 3 * a
            pts.append(lam[1:])
            wts.append(w)
    c = 0.04550370412564964949188053
    for pair in itertools.combinations(range(4), 2):
        lam = [0.5 - c if i in pair else c for i in range(4)]
        pts.append(lam[1:])
        wts.append(0.007091003462846911073011571)
    pts, wts = np.array(pts), np.array(wts)
    worst = 0.0
    for a in range(6):
        for b in range(6 - a):
            for c3 in range(6 - a - b):
                exact = math.factorial(a) * math.factorial(b) * math.factorial(c3) \
                    / math.factorial(a + b + c3 + 3)
                quad = (wts * pts[:, 0] ** a * pts[:, 1] ** b * pts[:, 2] ** c3).sum()
                worst = max(worst, abs(quad - exact) / exact)
    check_le('14-point degree-5 rule: every monomial of degree <= 5 integrated exactly, relative',
             worst, 1e-14, 'the rule\'s 25-digit parameters: round-off')
    return pts, wts


def scalar_mass_14(xyz, tets, density):
    """The scalar consistent mass (n x n, M = M_s (x) I3) with the 14-point rule, as ffrf integrates
    it: on curved Tet10 it differs from peer_tet10's exact one by the rule's error (~1e-11 in
    energy), which would otherwise be all that the eigen residuals measure."""
    import scipy.sparse as sp
    pts, wts = tet14_rule()
    l0 = 1 - pts.sum(axis=1)
    lam = np.column_stack([l0, pts])
    dlam = np.vstack([-np.ones(3), np.eye(3)])
    edges = ((0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3))
    n = np.zeros((len(pts), 10))
    dn = np.zeros((len(pts), 10, 3))
    for i in range(4):
        n[:, i] = lam[:, i] * (2 * lam[:, i] - 1)
        dn[:, i] = (4 * lam[:, i] - 1)[:, None] * dlam[i]
    for k, (a, b) in enumerate(edges):
        n[:, 4 + k] = 4 * lam[:, a] * lam[:, b]
        dn[:, 4 + k] = 4 * (lam[:, a][:, None] * dlam[b] + lam[:, b][:, None] * dlam[a])
    jac = np.einsum('eai,gaj->egij', xyz[tets], dn, optimize=True)
    me = density * np.einsum('ga,gb,eg->eab', n, n, np.linalg.det(jac) * wts, optimize=True)
    rows = np.repeat(tets, 10, axis=1).ravel()
    cols = np.tile(tets, (1, 10)).ravel()
    return sp.csr_matrix((me.ravel(), (rows, cols)), shape=(len(xyz), len(xyz)))


def apply_scalar(Ms, X):
    """(M_s (x) I3) X for X (3n, m)."""
    n = Ms.shape[0]
    return (Ms @ X.reshape(n, -1)).reshape(X.shape)


def tri6_area_centroid(xyz, tri):
    """Area and area centroid of curved Tri6 faces (Gmsh order: corners 0..2, mid-side nodes of
    the edges (0,1) (1,2) (2,0)), isoparametric, with a collapsed 8 x 8 Gauss rule."""
    x, w = np.polynomial.legendre.leggauss(8)
    x = 0.5 * (x + 1)
    w = 0.5 * w
    u, v = np.meshgrid(x, x, indexing='ij')
    wu, wv = np.meshgrid(w, w, indexing='ij')
    xi, eta = u.ravel(), (v * (1 - u)).ravel()
    wt = (wu * wv * (1 - u)).ravel()
    l = np.column_stack([1 - xi - eta, xi, eta])
    dl = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
    n = np.zeros((len(xi), 6))
    dn = np.zeros((len(xi), 6, 2))
    for i in range(3):
        n[:, i] = l[:, i] * (2 * l[:, i] - 1)
        dn[:, i] = (4 * l[:, i] - 1)[:, None] * dl[i]
    for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0))):
        n[:, 3 + k] = 4 * l[:, a] * l[:, b]
        dn[:, 3 + k] = 4 * (l[:, a][:, None] * dl[b] + l[:, b][:, None] * dl[a])
    xe = xyz[tri]                                            # (f, 6, 3)
    tangents = np.einsum('fai,gak->fgik', xe, dn, optimize=True)
    da = np.linalg.norm(np.cross(tangents[..., 0], tangents[..., 1]), axis=-1) * wt
    points = np.einsum('fai,ga->fgi', xe, n, optimize=True)
    area = float(da.sum())
    return area, (points * da[..., None]).sum(axis=(0, 1)) / area


def tet10_volume(xyz, tets):
    """int det J over the Tet10 mesh with a collapsed Gauss product rule of 3^3 points (exact to
    degree 5; det J of a curved Tet10 is cubic), written here rather than taken from peer_tet10."""
    x, w = np.polynomial.legendre.leggauss(3)
    x = 0.5 * (x + 1)
    w = 0.5 * w
    pts, wts = [], []
    for a, wa in zip(x, w):
        for b, wb in zip(x, w):
            for c, wc in zip(x, w):
                pts.append([a, b * (1 - a), c * (1 - a) * (1 - b)])
                wts.append(wa * wb * wc * (1 - a) ** 2 * (1 - b))
    pts, wts = np.array(pts), np.array(wts)
    l0 = 1 - pts.sum(axis=1)
    lam = np.column_stack([l0, pts])
    dlam = np.vstack([-np.ones(3), np.eye(3)])
    edges = ((0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3))
    dn = np.zeros((len(pts), 10, 3))
    for i in range(4):
        dn[:, i] = (4 * lam[:, i] - 1)[:, None] * dlam[i]
    for k, (a, b) in enumerate(edges):
        dn[:, 4 + k] = 4 * (lam[:, a][:, None] * dlam[b] + lam[:, b][:, None] * dlam[a])
    jac = np.einsum('eai,gaj->egij', xyz[tets], dn, optimize=True)
    return float((np.linalg.det(jac) * wts).sum())


# ------------------------------------------------------------------------------ modal files

def check_modal(h5, groups, mesh_dir, kind):
    for name in h5['bodies']:
        body = Body(h5, name, groups, mesh_dir)
        if kind == 'craig_bampton':
            check(body.basis == 'craig_bampton', f'[{name}] basis attribute {body.basis!r}')
        body.check_assembly()
        body.check_interfaces()
        label = 'CB' if body.basis == 'craig_bampton' else 'rc_normal'
        KP, MP, w2 = body.check_modes(label)
        computed = body.check_virtual_nodes(body.shape, body.vshape, label)
        body.check_mass_properties()
        if body.basis == 'craig_bampton':
            body.check_craig_bampton(KP, MP, w2, computed)
            body.check_residuals(KP, MP, w2, label, ritz=True)
        else:
            body.check_residuals(KP, MP, w2, label)
        sturm = body.group['modes'].get('sturm_check')
        if sturm is not None and text(sturm.attrs.get('status', b'off')) == 'proven':
            count = int(np.ravel(sturm['count'][()])[0])
            low = int(np.ravel(sturm['count_low'][()])[0])
            rigid = int(np.ravel(sturm['rigid_modes'][()])[0])
            # Craig-Bampton: the counts are those of the fixed-interface solve
            found = len(body.freq) if body.basis != 'craig_bampton' else \
                len(body.group['modes/fixed_interface_frequency'])
            check(count - low == found + rigid,
                  f'[{name}] Sturm counts: count - count_low = {count - low} = modes returned '
                  f'{found} + rigid {rigid}' + (' (fixed-interface solve)' if body.basis ==
                                                'craig_bampton' else ''))


# ------------------------------------------------------------------------------ mechanism files

def check_mechanism(h5, groups, mesh_dir):
    bodies = [g for g in groups if g.name == 'body']
    t = h5['time/t'][()]
    nsteps = len(t)
    q, v = h5['final_state/q'][()], h5['final_state/v'][()]
    offset = {}
    k = 0
    flex = {}
    for g in bodies:
        name = text(g.get('name'))
        rigid = text(g.get('type', 'flexible')) == 'rigid'
        m = 0 if rigid else h5[f'bodies/{name}/modes/frequency'].shape[0]
        offset[name] = (k, m)
        k += 7 + m
    check(k == len(q), f'/final_state/q holds {len(q)} coordinates, the bodies of the echo in '
          f'order [R, theta, zeta] {k}')
    # /final_state against the last recorded step: the same numbers
    same = True
    for name, (k0, m) in offset.items():
        row = np.concatenate([h5[f'bodies/{name}/position'][-1], h5[f'bodies/{name}/euler_parameters'][-1]]
                             + ([h5[f'bodies/{name}/modal_coordinates'][-1]] if m else []))
        same &= bool(np.array_equal(row, q[k0:k0 + 7 + m]))
    check(same and float(h5['final_state/t'][0]) == t[-1],
          '/final_state/{t, q} equal the last recorded step of /time/t and the body histories')

    # the time axis and the Euler normalisation theta^T theta = 1 (a constraint of every body)
    t_end = float(namelist.find(groups, 'integrator').get('t_end'))
    check(bool(np.all(np.diff(t) > 0)) and abs(t[-1] - t_end) <= 1e-12 * t_end,
          f'/time/t increasing from {t[0]} to t_end = {t_end} s of the echo (1e-12 relative)')
    worst = max(float(np.abs((h5[f'bodies/{text(g.get("name"))}/euler_parameters'][()] ** 2)
                             .sum(axis=1) - 1).max()) for g in bodies)
    check_le('Euler parameters of every body at every step: |theta^T theta - 1|', worst, 1e-13,
             'a constraint of the converged Newton steps: round-off growing with the steps, '
             'measured 3.3e-16 (0.02, 0.1 s), 1.6e-15 (0.2 s)')

    strain = np.zeros(nsteps)
    kinetic = 0.0
    vn_global = {}
    for g in bodies:
        name = text(g.get('name'))
        k0, m = offset[name]
        R = h5[f'bodies/{name}/position'][()]
        E = h5[f'bodies/{name}/euler_parameters'][()]
        qb, vb = q[k0:k0 + 7 + m], v[k0:k0 + 7 + m]
        A = euler_rotation(qb[3:7])
        omega_bar = euler_g_bar(qb[3:7]) @ vb[3:7]
        if m == 0:
            mass = float(g.get('mass'))
            c = np.array(g.get('center_of_mass'), float)
            j = np.array(g.get('inertia'), float)           # Jxx Jyy Jzz Jxy Jyz Jxz about c
            J = np.array([[j[0], j[3], j[5]], [j[3], j[1], j[4]], [j[5], j[4], j[2]]])
            # T = 1/2 m |v_c|^2 + 1/2 w^T J_c w, v_c = R_dot + A (w_bar x c)
            vc = vb[:3] + A @ np.cross(omega_bar, c)
            kinetic += 0.5 * mass * vc @ vc + 0.5 * omega_bar @ J @ omega_bar
            vn_global[name] = lambda step, x, R=R, E=E: R[step] + euler_rotation(E[step]) @ x
            continue
        body = Body(h5, name, groups, mesh_dir)
        flex[name] = body
        body.check_assembly()
        KP, _, _ = body.check_modes('mechanism')
        body.check_virtual_nodes(body.shape, body.vshape, 'mechanism')
        keep_vs = body.vshape
        kk = body.shape @ KP
        Z = h5[f'bodies/{name}/modal_coordinates'][()]          # (steps, m)
        strain += 0.5 * np.einsum('si,ij,sj->s', Z, kk, Z)
        # kinetic: nodal velocities in the body frame v_bar = A^T R_dot + w_bar x u_bar + Psi zeta_dot
        zeta, zdot = qb[7:], vb[7:]
        u = body.xyz.ravel() + body.shape.T @ zeta
        vel = np.tile(A.T @ vb[:3], len(body.xyz)) + np.cross(omega_bar, u.reshape(-1, 3)).ravel() \
            + body.shape.T @ zdot
        kinetic += 0.5 * vel @ apply_scalar(body.Ms14, vel)
        # virtual nodes: r_V = R + A (x_V + Psi_Vt zeta)
        def place(step, k, R=R, E=E, Z=Z, body=body, vs=keep_vs):
            j = body.order.index(k)
            return R[step] + euler_rotation(E[step]) @ (body.vn[k] + vs[:, 6 * j:6 * j + 3].T @ Z[step])
        vn_global[name] = place
        body.check_interfaces()
    stored_u = h5['energy/strain'][()]
    scale_u = max(np.abs(stored_u).max(), 1e-30)
    # the same quadratic form with K from another assembly: round-off relative to max U
    check_le('/energy/strain against sum_b 1/2 zeta^T (Psi K Psi^T) zeta at every step, / max U',
             float(np.abs(strain - stored_u).max() / scale_u), 5e-13,
             'assembly round-off, measured 4.6e-14')
    stored_t = h5['energy/kinetic'][()]
    check_le('/energy/kinetic at the end against T from /final_state {q, v} (rigid: input mass '
             'and inertia; flexible: 1/2 v^T M v of the rebuilt nodal velocities), relative',
             abs(kinetic / stored_t[-1] - 1), 1e-13,
             'M with the 14-point rule as ffrf: round-off, measured 2.2e-16 (4.6e-13 with the exact M)')
    W = h5['energy/external_work'][()]
    D = h5['energy/numerical_dissipation'][()]
    Dp = h5['energy/damping_dissipation'][()]
    balance = W - (stored_t + stored_u - stored_t[0] - stored_u[0]) - Dp - D
    scale = max(np.abs(W).max(), np.abs(stored_t).max(), np.abs(stored_u).max())
    check_le('balance D = W - (T + U - T0 - U0) - D_p of the stored series, every step, / max '
             'energy', float(np.abs(balance).max() / scale), 1e-14, 'an identity of the stored '
             'numbers: round-off, measured 0')
    check(bool(np.all(np.diff(Dp) >= -1e-15 * max(Dp.max(), 1e-30)) and np.all(Dp >= 0)),
          '/energy/damping_dissipation non-negative and non-decreasing (P_d = zeta_dot^T D zeta_dot '
          '>= 0)')

    # joints closed at every step (index 3: positions to the Newton tolerance)
    viol = float(np.ravel(h5['integrator/max_constraint_violation'][()])[0])
    joint_groups = [gj for gj in groups if gj.name == 'joint']
    markers = {(text(gm.get('body')), text(gm.get('name'))): np.array(gm.get('position'), float)
               for gm in groups if gm.name == 'marker'}

    def point(body, marker, step):
        if body == 'ground':
            return markers[('ground', marker)]
        if body in flex:
            return vn_global[body](step, marker)
        return vn_global[body](step, markers[(body, marker)])

    steps = range(nsteps)
    for gj in joint_groups:
        kind = text(gj.get('type'))
        b1, m1, b2, m2 = (text(gj.get(key)) for key in ('body1', 'marker1', 'body2', 'marker2'))
        if kind not in ('revolute', 'fixed', 'prismatic', 'cylindrical'):
            continue
        gap = np.array([point(b2, m2, s) - point(b1, m1, s) for s in steps])
        if kind in ('prismatic', 'cylindrical'):
            axis = np.array(gj.get('axis'), float)
            axis /= np.linalg.norm(axis)
            gap = gap - np.outer(gap @ axis, axis)
        worst = float(np.abs(gap).max())
        # the joints' point equations hold to the Newton tolerance (1e-10 atol on 1e-1 m
        # positions) at every step; the recorded rows are the converged states
        check_le(f'joint {text(gj.get("name"))} ({kind}): points {b1}.{m1} and {b2}.{m2} '
                 f'{"on the axis" if kind in ("prismatic", "cylindrical") else "coincide"} '
                 'at every step (m)',
                 worst, 1e-14, f'index 3: positions closed to round-off; '
                 f'/integrator/max_constraint_violation {viol:.2g}, measured <= 1.1e-16')
    # joint reactions: action and reaction (the force on body 2 opposite to that on body 1, the
    # moments about each body's joint point balanced with (p2 - p1) x F2)
    worst_f = worst_m = 0.0
    joint_points = {}
    for gj in joint_groups:
        jname = text(gj.get('name'))
        b1, m1, b2, m2 = (text(gj.get(key)) for key in ('body1', 'marker1', 'body2', 'marker2'))
        r = h5[f'joints/{jname}/reaction'][()]
        p1 = np.array([point(b1, m1, s) for s in steps])
        p2 = np.array([point(b2, m2, s) for s in steps])
        joint_points[jname] = (b1, p1, b2, p2, r)
        fmax = max(np.abs(r[:, 0:3]).max(), 1e-30)
        worst_f = max(worst_f, np.abs(r[:, 0:3] + r[:, 6:9]).max() / fmax)
        worst_m = max(worst_m, np.abs(r[:, 3:6] + r[:, 9:12] + np.cross(p2 - p1, r[:, 6:9])).max()
                      / (fmax * 0.1))
    check_le('/joints/*/reaction: F1 + F2 = 0 at every step, / max|F|', worst_f, 1e-15,
             'the same multipliers: round-off, measured 0')
    check_le('/joints/*/reaction: M1 + M2 + (p2 - p1) x F2 = 0 at every step, / (0.1 m max|F|)',
             worst_m, 1e-14, 'round-off, measured 2.5e-16')
    # Newton-Euler of each rigid body in impulse form against the stored reactions, the pressure
    # load (F = -(p - p_ref) pi bore^2 / 4 direction, docs/mechanisms.md "Mechanism runs") and
    # gravity: m v_c(t_end) = int F dt and, for a body turning in the xy plane, J_zz omega_z(t_end)
    # = int M_z dt about its centre, the integrals by the trapezoidal rule over the recorded steps,
    # the end velocities from /final_state/v; for a run from rest (v = 0 at t = 0)
    gravity = np.array(namelist.find(groups, 'mechanism').get('gravity', [0, 0, 0]), float)
    loads = [gl for gl in groups if gl.name == 'load']
    pressure = namelist.find_all(groups, 'pressure')
    force_scale = max(np.abs(r[:, 0:3]).max() for (_, _, _, _, r) in joint_points.values())
    from_rest = t[0] == 0.0 and h5['energy/kinetic'][0] == 0.0
    if not from_rest:
        print('note   Newton-Euler of the rigid bodies not checked: the run does not start from rest')
    for g in bodies:
        name = text(g.get('name'))
        if offset[name][1] != 0 or not from_rest:
            continue
        on_body = [gl for gl in loads if text(gl.get('body')) == name]
        if any(text(gl.get('type')) != 'pressure' for gl in on_body) or (on_body and not pressure):
            print(f'note   [{name}] Newton-Euler not checked: loads '
                  f'{[text(gl.get("type")) for gl in on_body]}')
            continue
        mass = float(g.get('mass'))
        c = np.array(g.get('center_of_mass'), float)
        jin = np.array(g.get('inertia'), float)
        R = h5[f'bodies/{name}/position'][()]
        E = h5[f'bodies/{name}/euler_parameters'][()]
        xc = R + np.einsum('sij,j->si', np.array([euler_rotation(e) for e in E]), c)
        force = np.tile(mass * gravity, (nsteps, 1))
        moment = np.zeros(nsteps)
        for jname, (b1, p1, b2, p2, r) in joint_points.items():
            for b, pj, cols in ((b1, p1, slice(0, 6)), (b2, p2, slice(6, 12))):
                if b == name:
                    f6 = r[:, cols]
                    force += f6[:, 0:3]
                    moment += f6[:, 5] + np.cross(pj - xc, f6[:, 0:3])[:, 2]
        for gl in on_body:
            pg = pressure[0]
            area = np.pi * float(pg.get('bore')) ** 2 / 4
            d = np.array(gl.get('direction'), float)
            d /= np.linalg.norm(d)
            fl = np.outer(-(h5['time/pressure'][()] - float(pg.get('reference_pressure'))) * area, d)
            pm = np.array([point(name, text(gl.get('marker')), st) for st in steps])
            force += fl
            moment += np.cross(pm - xc, fl)[:, 2]
        k0, _ = offset[name]
        qb, vb = q[k0:k0 + 7], v[k0:k0 + 7]
        omega_bar = euler_g_bar(qb[3:7]) @ vb[3:7]
        A = euler_rotation(qb[3:7])
        momentum = mass * (vb[:3] + A @ np.cross(omega_bar, c))
        impulse = np.trapz(force, t, axis=0)
        scale = max(np.abs(momentum).max(), 0.01 * force_scale * t[-1])
        # generalized-alpha integrates its algorithmic acceleration, the trapezoidal rule the
        # recorded forces: they differ by O(h) boundary terms ((gamma - 1/2) h (F_end - F_0)) and
        # the O(h^2) quadrature of the crank train's vibrations
        check_le(f'[{name}] rigid: m v_c(t_end) against int F dt of the stored joint reactions, '
                 'pressure load and gravity, / max(|m v_c|, 1 % of max|F_joint| t_end)',
                 float(np.abs(momentum - impulse).max() / scale), 3e-6, 'O(h) and O(h^2) '
                 'quadrature differences, measured <= 2.6e-7 (piston, 0.02 .. 0.2 s)')
        if np.abs(E[:, 1:3]).max() > 1e-6:
            continue
        omega_z = (A @ omega_bar)[2]
        angular = jin[2] * omega_z
        scale = max(abs(angular), 0.001 * force_scale * t[-1])
        check_le(f'[{name}] rigid: J_zz omega_z(t_end) against int M_z dt of the stored reactions '
                 'and loads about the centre, / max(|J w|, 0.1 % of max|F_joint| t_end 1 m)',
                 float(abs(angular - np.trapz(moment, t)) / scale), 3e-4, 'as above, growing '
                 'with time: measured 2.1e-7 (0.02 s), 3.9e-6 (0.1 s), 3.5e-5 (0.2 s, flywheel)')
    # crank angle and speed
    mech = namelist.find(groups, 'mechanism')
    crank = text(mech.get('crank', ''))
    if crank:
        E = h5[f'bodies/{crank}/euler_parameters'][()]
        raw = 2 * np.arctan2(E[:, 3], E[:, 0])
        angle = h5['time/crank_angle'][()]
        wrap = np.abs((angle - raw + np.pi) % (2 * np.pi) - np.pi).max()
        check_le('/time/crank_angle against 2 atan2(e3, e0) of the crank, modulo 2 pi (rad)',
                 float(wrap), 1e-14, 'round-off, measured 8.9e-16')
        check(bool(np.abs(np.diff(angle)).max() < np.pi),
              'crank angle unwrapped: steps below pi')
        k0, _ = offset[crank]
        speed = (2 * np.column_stack([-q[k0 + 4:k0 + 7], q[k0 + 3] * np.eye(3) + skew(q[k0 + 4:k0 + 7])])
                 @ v[k0 + 3:k0 + 7])[2]
        check_le('/time/crank_speed at the end against e_z . G(theta) theta_dot of /final_state, '
                 'relative', abs(speed / h5['time/crank_speed'][-1] - 1), 1e-14,
                 'the same formula: round-off, measured 0')
        check(float(h5['final_state/crank_angle'][0]) == angle[-1],
              '/final_state/crank_angle equals the last /time/crank_angle')


def check_file(results, mesh_dir=None, kind=None, reused=False, restarted=False):
    """Every check of one results file; returns the failed checks (also in FAILURES)."""
    first = len(FAILURES)
    with h5py.File(results, 'r') as h5:
        status = text(h5.attrs['status'])
        check(status == 'complete', f'status {status!r}')
        groups = namelist.parse(text(h5['input/namelist']), source='/input/namelist')
        is_mech = 'time' in h5
        if kind:
            check(is_mech == (kind == 'mechanism'),
                  f'the file is a {"mechanism" if is_mech else "modal"} run')
        if restarted:
            check('restart_origin' in h5, 'the file is a restarted run (/restart_origin)')
        if reused:
            flexible = [g for g in groups if g.name == 'body' and
                        text(g.get('type', 'flexible')) == 'flexible']
            check(bool(flexible) and all(text(g.get('modes_file', '')) for g in flexible),
                  'every flexible body took its modes from a modes_file (input echo)')
        if is_mech:
            check_mechanism(h5, groups, mesh_dir)
        else:
            check_modal(h5, groups, mesh_dir, kind)
    return FAILURES[first:]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('results')
    parser.add_argument('--mesh-dir', help='folder of the mesh files (mechanism files)')
    parser.add_argument('--kind', choices=('modal', 'craig_bampton', 'mechanism'),
                        help='what the file must be')
    parser.add_argument('--reused', action='store_true',
                        help='every flexible body must have taken its modes from &body modes_file')
    parser.add_argument('--restarted', action='store_true',
                        help='the file must come from --restart (/restart_origin)')
    parser.add_argument('--skip-missing', action='store_true',
                        help='exit 77 (skipped) when RESULTS does not exist (the MPI run)')
    args = parser.parse_args()
    if args.skip_missing and not os.path.exists(args.results):
        print(f'skipped: {args.results} does not exist (no MPI build, see mpi_build)')
        sys.exit(77)
    t0 = time.time()
    check_file(args.results, args.mesh_dir, args.kind, args.reused, args.restarted)
    print(f'{time.time() - t0:.1f} s')
    if FAILURES:
        print(f'{len(FAILURES)} check(s) failed')
        sys.exit(1)
    print('check_results_independent: all checks passed')


if __name__ == '__main__':
    main()
