"""Every value-returning C API entry point, on every path, against the ffrf driver (issue 28, 4).

test_capi_values dumps what each entry point returns on six paths (its header: the line
format); this script runs the ffrf driver on the same cases and compares every value with the
driver's results file, or, where the file does not hold it, with an independent recomputation
here. Driver runs (OUT_DIR/driver/...):
  modal/      the modal case (crank lc 8 mm, RC set 2, 8 modes: `modal file` below);
  mechanism/  the engine case (lc 8 mm, flexible crank and conrod with 10 modes, h = 1e-4 s,
              t_end = 5 ms);
  t<k>/       the engine case with --set integrator.t_end = the driver's time after k
              chunks (k = 1 .. K-1), the modes reused from mechanism/ (&body modes_file):
              its /final_state holds the velocities after chunk k, which no series holds;
  bodies/     a modal case of the engine's meshed bodies (their &body and &interface groups
              of the resolved input): /bodies/<b>/mesh and /mass, which a mechanism file does
              not hold.

Paths (P): (a) modal_quiet, (b) modal_output: a modal ffrf_case_run without / with an output
folder; (c) chunks_quiet, (d) chunks_output: the engine advanced in 1 ms chunks without / with
an output folder (state after the first advance to t_start and after every chunk); (e)
run_quiet, run_output: the engine run to t_end by one ffrf_case_run without / with an output
folder; (f) arrays_modal: the modal case's body built from arrays (ffrf_case_new,
ffrf_case_add_body, ffrf_case_add_interface_nodes with the driver's interface nodes, virtual
nodes and reference conditions, ffrf_case_set_num_modes; arrays.txt written here from the
driver's modal file), then ffrf_case_run: its modes are the driver's bitwise.

Matrix: entry point x paths, reference, tolerance. "bitwise" = 0: the API returns the very
doubles the driver computed, through the same code and (mechanism) the same steps: the modes
come from compute_body_modes for both, the chunks are multiples of h (docs/api.md "Concepts").
  ffrf_version               all    /attrs ffrf_version of the driver's files        exact
  ffrf_body_count, _name     all    the &body groups of the driver's resolved input
                                    (/input/namelist), in order                    exact
  ffrf_body_sizes            all    /bodies/<b>/mesh/coordinates rows, modes/frequency
                                    length, interfaces/order length; rigid: 0 0 0   exact
  ffrf_body_frequencies      all    /bodies/<b>/modes/frequency (rigid: none)       bitwise
  ffrf_body_mode_shapes      all    /bodies/<b>/modes/shape                         bitwise
  ffrf_body_virtual_node_shapes all /bodies/<b>/modes/virtual_node_shape            bitwise
  ffrf_body_nodes            a b f  modal file /bodies/<b>/mesh/coordinates         bitwise
                             c-e    bodies file, the same                           bitwise
  ffrf_body_mass_properties  a b f  modal file /bodies/<b>/mass/*                   bitwise
                             c-e    bodies file, the same (rigid bodies without a mesh:
                                    FFRF_BAD_CALL)                                  bitwise
                             all    and the consistent mass integrated here in numpy from
                                    the driver's mesh (TET14_RULE)                  MASS_RTOL
  ffrf_body_invariant (all   all    recomputed here from the numpy mass matrix, the driver's
   eleven names)                    mesh, mode shapes and frequencies (theory.md 3.2; the
                                    file holds no invariant); rigid: FFRF_BAD_CALL  GRAM_RTOL
  ffrf_mechanism_time        c d    /time/t row of the chunk's end, bitwise; t_end = the
                                    resolved &integrator t_end                      bitwise
                             e      /final_state/t                                  bitwise
  ffrf_crank_state           c d    /time/{crank_angle, crank_speed} at that row    bitwise
                             e      their last row                                  bitwise
  ffrf_body_state q          c d e  /bodies/<b>/{position, euler_parameters,
                                    modal_coordinates} at that row, and /final_state/q
                                    at t_end                                        bitwise
  ffrf_body_state v          c d    t = 0: /energy/kinetic is 0 there, so v = 0 (M > 0),
                                    and at t_end: /final_state/v                    bitwise
                                    after chunk k < K: /final_state/v of the driver run
                                    t<k> (its last step is the remainder)      VELOCITY_RTOL
                             e      /final_state/v                                  bitwise
  ffrf_marker_count          c d e  flexible: interfaces/order; rigid: one per distinct
                                    (&marker, joint axis) of the joints' ends and loads
                                    (z axis), src/app/mechanism_builder.f90          exact
  ffrf_marker_state          c d e  recomputed from the (checked) body state: flexible
                                    r = R + A (x_V + Psi_Vt zeta), v = R' + w x A u +
                                    A Psi_Vt zeta', w_V = A (w_bar + J(phi) Psi_Vr zeta')
                                    with the driver's virtual_node and virtual_node_shape;
                                    rigid r = R + A s (s the &marker point), v = R' +
                                    w x A s, w_V = w                     MARKER_RTOL
  ffrf_joint_count, _name    c d e  the &joint groups of the resolved input, in order exact
  ffrf_joint_reaction        c d e  /joints/<j>/reaction at that row, where
                                    /joints/<j>/reaction_min_norm is 0: the API returns the
                                    raw multipliers, the driver the minimum-norm split of
                                    near-redundant rows (src/mbs/reaction_split.f90); a
                                    flagged component is reported, not compared      bitwise
                                    This engine has no near-redundant row (every flag 0), so
                                    raw and reported reactions are one. On a case with such
                                    rows (issue 30's variant: piston 0.9 kg, compression
                                    ratio 12, crank lc 10 mm with 4 modes, conrod 2 modes)
                                    they differ at flagged components (API 3.2e4 N of
                                    self-stress, driver 0.07 N); the unflagged ones agree
                                    within 1e-3 of the state's largest reaction (the split's
                                    flag threshold; capi_values_variant). A first flag rule
                                    left moved components unflagged (cylinder moment 1914
                                    N m against 2e-4 N m), found here.
  run_output (e, with an output folder): the run is over and written: body_state,
  marker_count, marker_state, joint_count must answer FFRF_BAD_CALL (docs/api.md); the body
  data, time and crank state are compared as above. Status of every call: FFRF_OK where a
  value is expected (and ffrf_last_error "" then, checked in C).
  ffrf_marker_set_load (no value): a zero load set at t_start on paths c and d; the states
  are still the driver's bitwise.
The results files the API writes on paths b, d, e hold the driver's frequencies, shapes,
time series and reactions bitwise (the whole file: capi_record_driver, capi_compare_driver).
The case-building entry points of path f (ffrf_case_new, _add_body, _add_interface_nodes,
_set_num_modes) return statuses only (checked in C); their result is f's body data.
Usage: compare_values.py FFRF TEST_CAPI_VALUES MODAL_CASE MECHANISM_CASE MESH_DIR OUT_DIR CHUNK
"""
import os
import re
import shutil
import subprocess
import sys
import time

import h5py
import numpy as np
import scipy.sparse

# Mass properties integrated here against the library's: the same quadrature rule (the
# 14-point degree-5 rule of Walkington (2000), here from its orbit parameters) on the same
# elements in another summation order: round-off of sums of ~1e5 positive and negative
# element entries, ~1e-15 relative measured; 1e-12 leaves room for other BLAS kernels and
# compilers and is still 1e9 times below any wrong node, element or index.
MASS_RTOL = 1e-12
# Invariants Z1^T M Z2: entry (i, j) to GRAM_RTOL * s_i s_j, s the M-norms of the columns
# (Cauchy-Schwarz bounds |entry| by s_i s_j): the summation error of a Gram sum of ~1e5
# terms is a few hundred eps of that bound at worst.
GRAM_RTOL = 1e-11
# Velocities after a chunk against the driver's run to that time (/final_state/v): that run's
# last step is t_k - t_(k-1) (galpha_step lands on t_end with the remainder), which differs
# from h by the rounding of t_(k-1) + h (<= 4e-15 h); the states differ at that level
# (measured <= 3e-15 of the body's largest velocity coordinate). 1e-12 of that largest value.
VELOCITY_RTOL = 1e-12
# Marker states recomputed from the body state in numpy: the library's Jacobian products in
# another order: a few eps of the largest term (R, A u, omega x A u); 1e-13 of the scale.
MARKER_RTOL = 1e-13

PATHS = ('modal_quiet', 'modal_output', 'chunks_quiet', 'chunks_output', 'run_quiet',
         'run_output', 'arrays_modal')
RC_WORDS = ('Tx', 'Ty', 'Tz', 'Rx', 'Ry', 'Rz')
MPC_CODES = {'RBE2': 1, 'RBE3': 2}          # FFRF_RBE2, FFRF_RBE3 of include/ffrf.h
INVARIANTS = ('mass', 'center_of_mass', 'theta_u', 'M_PhitPsi', 'M_PhitPsit', 'M_xPsi',
              'M_xPsit', 'M_PsitPsi', 'M_PsitPsit', 'M_PsiPsi', 'K_ff')


# ------------------------------------------------------------------ reading

def run(command, cwd=None):
    print('+', ' '.join(command), flush=True)
    if subprocess.run(command, cwd=cwd).returncode != 0:
        sys.exit(f'{command[0]} failed')


def read_dump(path):
    """{(entry, keys...): (status, text of the values)}; version: status 0."""
    table = {}
    with open(path) as f:
        for line in f:
            left, _, right = line.rstrip('\n').partition(' :')
            words = left.split()
            if words[0] == 'version':
                table[('version',)] = (0, right.strip())
                continue
            table[tuple(words[:-1])] = (int(words[-1]), right.strip())
    return table


def numbers(text):
    return np.array(text.split(), dtype=float) if text else np.zeros(0)


def namelist(file):
    """The groups of a resolved input (/input/namelist): [(group, {key: [values]})]."""
    text = file['/input/namelist'][()]
    text = text.decode() if isinstance(text, bytes) else str(text)
    groups = []
    for line in text.splitlines():
        line = line.strip()
        if not line.startswith('&'):
            continue
        name, _, body = line[1:].partition(' ')
        body = body.rstrip().rstrip('/')
        # key = value ... key = value: split at "key =" outside quotes
        tokens = re.findall(r"'[^']*'|[^\s,=]+|=", body)
        keys = {}
        key = None
        for i, token in enumerate(tokens):
            if token == '=':
                continue
            if i + 1 < len(tokens) and tokens[i + 1] == '=':
                key = token
                keys[key] = []
            elif token.startswith("'"):
                keys[key].append(token[1:-1])
            else:
                keys[key].append(token)
        groups.append((name, keys))
    return groups


def version_of(file):
    v = file.attrs['ffrf_version']
    return (v.decode() if isinstance(v, bytes) else str(v)).replace('.', ' ')


# ------------------------------------------------------------------ independent mass matrix

def tet14_rule():
    """Walkington's 14-point degree-5 rule on the reference tetrahedron (volume 1/6)."""
    a1, w1 = 0.3108859192633006097973457, 0.01878132095300264179986428
    a2, w2 = 0.09273525031089122640232391, 0.01224884051939365825728503
    c, w3 = 0.04550370412564964949188053, 0.007091003462846911073011571
    points, weights = [], []
    for a, w in ((a1, w1), (a2, w2)):
        b = 1.0 - 3.0 * a
        for corner in range(4):
            bary = [a] * 4
            bary[corner] = b
            points.append(bary)
            weights.append(w)
    d = 0.5 - c
    for i in range(4):
        for j in range(i + 1, 4):
            bary = [c] * 4
            bary[i] = bary[j] = d
            points.append(bary)
            weights.append(w3)
    return np.array(points), np.array(weights)


def tet10_shapes(bary):
    """Gmsh Tet10 shape functions and their derivatives in (u, v, w) at barycentric points
    (L1 = 1 - u - v - w, L2 = u, L3 = v, L4 = w); edges (1,2) (2,3) (1,3) (1,4) (3,4) (2,4)."""
    dL = np.array([[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    edges = ((0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3))
    q = bary.shape[0]
    N = np.zeros((q, 10))
    dN = np.zeros((q, 10, 3))
    for c in range(4):
        N[:, c] = bary[:, c] * (2.0 * bary[:, c] - 1.0)
        dN[:, c, :] = np.outer(4.0 * bary[:, c] - 1.0, dL[c])
    for e, (i, j) in enumerate(edges):
        N[:, 4 + e] = 4.0 * bary[:, i] * bary[:, j]
        dN[:, 4 + e, :] = 4.0 * (np.outer(bary[:, j], dL[i]) + np.outer(bary[:, i], dL[j]))
    return N, dN


def scalar_mass(xyz, tets, density):
    """Consistent scalar mass Ms (n x n, sparse): rho int N_a N_b dV, element by element."""
    bary, weights = tet14_rule()
    if tets.shape[1] == 10:
        N, dN = tet10_shapes(bary)
    else:
        N = bary
        dN = np.broadcast_to(np.array([[-1.0, -1.0, -1.0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]),
                             (len(weights), 4, 3))
    xe = xyz[tets]                                         # (ne, nen, 3)
    jac = np.einsum('qai,eaj->eqij', dN, xe)               # dx_j / du_i
    det = np.linalg.det(jac)
    if not np.all(det > 0):
        sys.exit('numpy mass: an element with det J <= 0')
    me = density * np.einsum('eq,qa,qb->eab', det * weights, N, N)
    rows = np.repeat(tets, tets.shape[1], axis=1).ravel()
    cols = np.tile(tets, (1, tets.shape[1])).ravel()
    n = xyz.shape[0]
    return scipy.sparse.coo_matrix((me.ravel(), (rows, cols)), shape=(n, n)).tocsr()


def skew(p):
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


class Body:
    """A meshed body of the driver's files: mesh, density, modes, and what is derived here."""

    def __init__(self, mesh_group, density, frequency, shape):
        self.xyz = mesh_group['coordinates'][()]
        tets = mesh_group['tets'][()]
        # the file's tets hold node numbers 1..n (Fortran) of the mesh/coordinates rows
        self.tets = tets.astype(np.int64) - 1
        self.Ms = scalar_mass(self.xyz, self.tets, density)
        self.frequency = frequency
        self.shape = shape                                  # (m, 3n)

    def mass_properties(self):
        Ms, X = self.Ms, self.xyz
        mass = Ms.sum()
        center = np.asarray(Ms.sum(axis=0)).ravel() @ X / mass
        Y = X - center
        S = Y.T @ (Ms @ Y)
        S = 0.5 * (S + S.T)
        return mass, center, np.trace(S) * np.eye(3) - S

    def invariants(self):
        """theory.md 3.2, written out for M = Ms (x) I3: {name: (values column-major, scale)}."""
        Ms, X = self.Ms, self.xyz
        m = self.shape.shape[0]
        n = X.shape[0]
        P = self.shape.reshape(m, n, 3)                     # P[k] = mode k per node
        ones = np.ones(n)
        row = Ms @ ones
        MX = Ms @ X
        MP = np.stack([Ms @ P[k] for k in range(m)])        # (m, n, 3)
        mass = ones @ row
        S = X.T @ MX
        theta_u = np.trace(S) * np.eye(3) - S
        phit_psi = np.stack([ones @ MP[k] for k in range(m)], axis=1)        # 3 x m
        phit_psit = np.hstack([skew(phit_psi[:, k]) for k in range(m)])     # 3 x 3m
        x_psi = np.stack([-np.sum(np.cross(X, MP[k]), axis=0) for k in range(m)], axis=1)
        x_psit = np.hstack([np.trace(X.T @ MP[k]) * np.eye(3) - MP[k].T @ X for k in range(m)])
        psit_psi = np.zeros((3 * m, m))
        psit_psit = np.zeros((3 * m, 3 * m))
        psi_psi = np.zeros((m, m))
        for k in range(m):
            for l in range(m):
                psit_psi[3 * k:3 * k + 3, l] = -np.sum(np.cross(P[k], MP[l]), axis=0)
                D = MP[l].T @ P[k]
                psit_psit[3 * k:3 * k + 3, 3 * l:3 * l + 3] = np.trace(D) * np.eye(3) - D
                psi_psi[k, l] = np.sum(P[k] * MP[l])
        # column M-norms: Phi_t sqrt(m), x~ sqrt(diag theta_u), Psi and Psi~ their Gram diagonals
        s_t = np.full(3, np.sqrt(mass))
        s_x = np.sqrt(np.diag(theta_u))
        s_p = np.sqrt(np.diag(psi_psi))
        s_pt = np.sqrt(np.diag(psit_psit))
        s_1 = np.sqrt(np.sum(X * MX)) * np.ones(1)          # the x column (centre of mass)
        table = {
            'mass': (np.array([mass]), np.array([[mass]])),
            'center_of_mass': (np.asarray(row @ X / mass), np.outer(s_t, s_1) / mass),
            'theta_u': (theta_u, np.outer(s_x, s_x)),
            'M_PhitPsi': (phit_psi, np.outer(s_t, s_p)),
            'M_PhitPsit': (phit_psit, np.outer(s_t, s_pt)),
            'M_xPsi': (x_psi, np.outer(s_x, s_p)),
            'M_xPsit': (x_psit, np.outer(s_x, s_pt)),
            'M_PsitPsi': (psit_psi, np.outer(s_pt, s_p)),
            'M_PsitPsit': (psit_psit, np.outer(s_pt, s_pt)),
            'M_PsiPsi': (psi_psi, np.outer(s_p, s_p)),
            'K_ff': ((2.0 * np.pi * self.frequency) ** 2, (2.0 * np.pi * self.frequency) ** 2),
        }
        return {k: (np.ravel(v, order='F'), np.ravel(s, order='F')) for k, (v, s) in
                table.items()}


# ------------------------------------------------------------------ rotations

def rotation(p):
    e0, e = p[0], p[1:4]
    return (2.0 * e0 ** 2 - 1.0) * np.eye(3) + 2.0 * np.outer(e, e) + 2.0 * e0 * skew(e)


def omega_global(p, dp):
    """w = G(p) p', G = 2 [-e, e0 I + e~]."""
    G = np.hstack([-p[1:4, None], p[0] * np.eye(3) + skew(p[1:4])])
    return 2.0 * G @ dp


def exp_tangent(phi):
    """Left Jacobian of exp: d/dt exp(phi~) exp(-phi~) = (J phi')~."""
    angle = np.linalg.norm(phi)
    K = skew(phi)
    if angle < 1e-2:
        # series: the closed form loses (1 - cos) to cancellation at the elastic rotations
        # (~1e-6 rad); the next terms are O(angle^4)
        return (np.eye(3) + (0.5 - angle ** 2 / 24.0) * K +
                (1.0 / 6.0 - angle ** 2 / 120.0) * K @ K)
    return (np.eye(3) + (1.0 - np.cos(angle)) / angle ** 2 * K +
            (angle - np.sin(angle)) / angle ** 3 * K @ K)


# ------------------------------------------------------------------ comparison

class Report:
    def __init__(self):
        self.failures = []
        self.worst = {}          # (entry, path) -> (largest difference, tolerance, count)
        self.notes = []
        self.refusals = {}       # (entry, path) -> the status expected instead of a value

    def compare(self, path, entry, what, got, expected, tolerance=0.0, scale=None):
        """|got - expected| <= tolerance (times scale per value, when given); 0: bitwise."""
        got = np.asarray(got, dtype=float).ravel()
        expected = np.asarray(expected, dtype=float).ravel()
        key = (entry, path)
        if got.shape != expected.shape:
            self.failures.append(f'{path}: {entry} {what}: {got.size} values, expected '
                                 f'{expected.size}')
            self.worst[key] = (np.inf, tolerance, self.worst.get(key, (0, 0, 0))[2] + 1)
            return
        diff = np.abs(got - expected)
        if tolerance == 0.0:
            ok = np.array_equal(got, expected)
            measure = float(diff.max()) if diff.size else 0.0
        else:
            bound = tolerance * (np.asarray(scale, dtype=float).ravel() if scale is not None
                                 else np.ones_like(expected))
            ok = bool(np.all(diff <= bound))
            measure = float(np.max(diff / np.where(bound > 0, bound / tolerance, 1.0))) \
                if diff.size else 0.0
        previous = self.worst.get(key, (0.0, tolerance, 0))
        self.worst[key] = (max(previous[0], measure), tolerance, previous[2] + 1)
        if not ok:
            self.failures.append(f'{path}: {entry} {what}: differs by {measure:.3g} '
                                 f'(tolerance {tolerance:g})')

    def equal(self, path, entry, what, got, expected):
        key = (entry, path)
        previous = self.worst.get(key, (0.0, 0.0, 0))
        self.worst[key] = (previous[0] if got == expected else np.inf, 0.0, previous[2] + 1)
        if got != expected:
            self.failures.append(f'{path}: {entry} {what}: {got!r}, expected {expected!r}')

    def status(self, path, entry, what, got, expected):
        if expected != 0:
            # an answer expected to be a refusal: shown in the summary as "status <code>"
            self.refusals[(entry, path)] = expected
        if got != expected:
            self.failures.append(f'{path}: {entry} {what}: status {got}, expected {expected}')


def value(dump, *key):
    if key not in dump:
        return None, None
    return dump[key]


def check_body_data(report, path, dump, case_groups, files, derived):
    """Body data of every body. files[name]: (modes group, mesh and mass group or None)."""
    bodies = [g for name, g in case_groups if name == 'body']
    status, text = value(dump, 'body_count')
    report.status(path, 'ffrf_body_count', '', status, 0)
    report.equal(path, 'ffrf_body_count', '', int(text), len(bodies))
    for b, body in enumerate(bodies):
        name = body['name'][0]
        status, text = value(dump, 'body_name', str(b))
        report.status(path, 'ffrf_body_name', name, status, 0)
        report.equal(path, 'ffrf_body_name', f'body {b}', text, name)
        meshed = body.get('mesh_file', [''])[0] != ''
        sizes = [int(x) for x in value(dump, 'body_sizes', str(b))[1].split()]
        if not meshed:
            report.equal(path, 'ffrf_body_sizes', name, sizes, [0, 0, 0])
            report.equal(path, 'ffrf_body_frequencies', name,
                         value(dump, 'body_frequencies', str(b)), (0, ''))
            for entry in ('body_nodes', 'body_mode_shapes', 'body_virtual_node_shapes'):
                report.equal(path, 'ffrf_' + entry, name, value(dump, entry, str(b)), (0, ''))
            report.status(path, 'ffrf_body_mass_properties', name + ' (no mesh)',
                          value(dump, 'body_mass_properties', str(b))[0], 1)
            for inv in INVARIANTS:
                report.status(path, 'ffrf_body_invariant', f'{name} {inv} (rigid)',
                              value(dump, 'body_invariant', str(b), inv)[0], 1)
            continue
        modes, mesh_mass = files[name]
        frequency = modes['modes/frequency'][()]
        shape = modes['modes/shape'][()]
        virtual = modes['modes/virtual_node_shape'][()]
        coordinates = mesh_mass['mesh/coordinates'][()]
        report.equal(path, 'ffrf_body_sizes', name, sizes,
                     [coordinates.shape[0], len(frequency), len(modes['interfaces/order'])])
        for entry, reference in (('body_frequencies', frequency), ('body_nodes', coordinates),
                                 ('body_mode_shapes', shape),
                                 ('body_virtual_node_shapes', virtual)):
            status, text = value(dump, entry, str(b))
            report.status(path, 'ffrf_' + entry, name, status, 0)
            # h5py shows a Fortran (r, c) array as (c, r): its C order is the API's
            # column-major order
            report.compare(path, 'ffrf_' + entry, name, numbers(text), reference.ravel())
        status, text = value(dump, 'body_mass_properties', str(b))
        report.status(path, 'ffrf_body_mass_properties', name, status, 0)
        got = numbers(text)
        report.compare(path, 'ffrf_body_mass_properties', name + ' vs driver', got,
                       np.concatenate([[mesh_mass['mass/mass'][()]],
                                       mesh_mass['mass/center_of_mass'][()],
                                       mesh_mass['mass/inertia'][()].ravel()]))
        body_derived = derived[name]
        mass, center, inertia = body_derived.mass_properties()
        length = np.max(np.abs(body_derived.xyz))
        scale = np.concatenate([[mass], np.full(3, length), np.full(9, mass * length ** 2)])
        report.compare(path, 'ffrf_body_mass_properties (numpy)', name, got,
                       np.concatenate([[mass], center, inertia.ravel()]), MASS_RTOL, scale)
        invariants = body_derived.invariants_cache
        for inv in INVARIANTS:
            status, text = value(dump, 'body_invariant', str(b), inv)
            report.status(path, 'ffrf_body_invariant', f'{name} {inv}', status, 0)
            reference, scale = invariants[inv]
            report.compare(path, 'ffrf_body_invariant', f'{name} {inv}', numbers(text),
                           reference, GRAM_RTOL, scale)


def rigid_markers(case_groups, body):
    """&marker points of a rigid body's markers, in the builder's order: one per distinct
    (point, joint axis) over the joints' ends in order, then the loads (z axis)."""
    points = {g['name'][0]: np.array(g['position'], dtype=float)
              for n, g in case_groups if n == 'marker' and g['body'][0] == body}
    seen = []
    for n, g in case_groups:
        if n == 'joint':
            axis = tuple(float(x) for x in g.get('axis', ['0', '0', '1']))
            for end in ('1', '2'):
                if g['body' + end][0] == body and (g['marker' + end][0], axis) not in seen:
                    seen.append((g['marker' + end][0], axis))
    for n, g in case_groups:
        if n == 'load' and g['body'][0] == body and (g['marker'][0], (0.0, 0.0, 1.0)) not in seen:
            seen.append((g['marker'][0], (0.0, 0.0, 1.0)))
    return [points[name] for name, _ in seen]


def check_state(report, path, dump, k, case_groups, driver, velocity_files):
    """The mechanism state dumped as state k, against the driver's row at its time;
    velocity_files: the driver's long run, then its runs to the chunks' ends."""
    mechanism_end = velocity_files[0]
    bodies = [g for name, g in case_groups if name == 'body']
    joints = [g['name'][0] for name, g in case_groups if name == 'joint']
    t_end = float([g for n, g in case_groups if n == 'integrator'][0]['t_end'][0])
    status, text = value(dump, 'mechanism_time', str(k))
    report.status(path, 'ffrf_mechanism_time', f'state {k}', status, 0)
    t, t_end_api = numbers(text)
    report.compare(path, 'ffrf_mechanism_time', 't_end', [t_end_api], [t_end])
    times = driver['/time/t'][()]
    rows = np.nonzero(times == t)[0]
    if len(rows) != 1:
        report.failures.append(f'{path}: state {k}: no driver row at t = {t!r}')
        return
    row = rows[0]
    report.compare(path, 'ffrf_mechanism_time', f't (state {k})', [t], [times[row]])
    status, text = value(dump, 'crank_state', str(k))
    report.status(path, 'ffrf_crank_state', f'state {k}', status, 0)
    report.compare(path, 'ffrf_crank_state', f'state {k}', numbers(text),
                   [driver['/time/crank_angle'][row], driver['/time/crank_speed'][row]])
    recorded = path == 'run_output'
    # velocities: t = 0 (at rest: kinetic energy 0), or a driver run ending at t
    reference_v = None
    if row == 0 and driver['/energy/kinetic'][0] == 0.0:
        reference_v = 'rest'
    for f in velocity_files:
        if f['/final_state/t'][0] == t:
            reference_v = f
    if reference_v is None and not recorded:
        report.failures.append(f'{path}: state {k} (t = {t}): no reference for the velocities')
    offset = 0
    for b, body in enumerate(bodies):
        name = body['name'][0]
        modes = int(value(dump, 'body_sizes', str(b))[1].split()[1])
        count = 7 + modes
        status, text = value(dump, 'body_state', str(k), str(b))
        marker_status, marker_text = value(dump, 'marker_count', str(k), str(b))
        if recorded:
            for entry, got in (('ffrf_body_state q', status), ('ffrf_body_state v', status),
                               ('ffrf_marker_count', marker_status),
                               ('ffrf_marker_state', value(dump, 'marker_state', str(k),
                                                           str(b), '0')[0])):
                report.status(path, entry, f'{name} after a recorded run', got, 1)
            continue
        report.status(path, 'ffrf_body_state q', name, status, 0)
        qv = numbers(text)
        if qv.size != 2 * count:
            report.failures.append(f'{path}: body_state {name}: {qv.size} values, expected '
                                   f'2 x {count}')
            offset += count
            continue
        q, v = qv[:count], qv[count:]
        group = driver['/bodies/' + name]
        expected_q = np.concatenate([group['position'][row], group['euler_parameters'][row]] +
                                    ([group['modal_coordinates'][row]] if modes else []))
        report.compare(path, 'ffrf_body_state q', f'{name} state {k}', q, expected_q)
        if t == driver['/final_state/t'][0]:
            report.compare(path, 'ffrf_body_state q', f'{name} /final_state', q,
                           driver['/final_state/q'][offset:offset + count])
        if isinstance(reference_v, str):
            report.compare(path, 'ffrf_body_state v', f'{name} at rest', v, np.zeros(count))
        elif reference_v is mechanism_end:
            report.compare(path, 'ffrf_body_state v', f'{name} at t_end', v,
                           reference_v['/final_state/v'][offset:offset + count])
        elif reference_v is not None:
            report.compare(path, 'ffrf_body_state v (chunk ends)', f'{name} state {k}', v,
                           reference_v['/final_state/v'][offset:offset + count], VELOCITY_RTOL,
                           np.full(count, np.max(np.abs(v))))
        offset += count
        # markers
        report.status(path, 'ffrf_marker_count', name, marker_status, 0)
        R, p, zeta = q[0:3], q[3:7], q[7:]
        dR, dp, dzeta = v[0:3], v[3:7], v[7:]
        A = rotation(p)
        w = omega_global(p, dp)
        if modes:
            order = [x.decode() if isinstance(x, bytes) else str(x)
                     for x in group['interfaces/order'][()]]
            rows6 = driver[f'/bodies/{name}/modes/virtual_node_shape'][()].T   # (6 nif, m)
            local = [(group[f'interfaces/{i}/virtual_node'][()], rows6[6 * j:6 * j + 6])
                     for j, i in enumerate(order)]
        else:
            local = [(s, None) for s in rigid_markers(case_groups, name)]
        report.equal(path, 'ffrf_marker_count', name, int(marker_text), len(local))
        for m, (s, rows) in enumerate(local):
            status, text = value(dump, 'marker_state', str(k), str(b), str(m))
            report.status(path, 'ffrf_marker_state', f'{name} {m}', status, 0)
            if rows is None:
                u = s
                r = R + A @ u
                vel = dR + np.cross(w, A @ u)
                omega = w
            else:
                u = s + rows[0:3] @ zeta
                phi = rows[3:6] @ zeta
                r = R + A @ u
                vel = dR + np.cross(w, A @ u) + A @ (rows[0:3] @ dzeta)
                omega = w + A @ (exp_tangent(phi) @ (rows[3:6] @ dzeta))
            lever = np.linalg.norm(u)
            scale = np.concatenate([np.full(3, np.linalg.norm(R) + lever),
                                    np.full(3, np.linalg.norm(dR) + np.linalg.norm(w) * lever +
                                            np.linalg.norm(vel)),
                                    np.full(3, np.linalg.norm(w) + np.linalg.norm(omega))])
            report.compare(path, 'ffrf_marker_state', f'{name} marker {m} state {k}',
                           numbers(text), np.concatenate([r, vel, omega]), MARKER_RTOL,
                           np.maximum(scale, 1e-300))
    status, text = value(dump, 'joint_count', str(k))
    if recorded:
        for entry, got in (('ffrf_joint_count', status),
                           ('ffrf_joint_name', value(dump, 'joint_name', str(k), '0')[0]),
                           ('ffrf_joint_reaction', value(dump, 'joint_reaction', str(k),
                                                         '0')[0])):
            report.status(path, entry, 'after a recorded run', got, 1)
        return
    report.status(path, 'ffrf_joint_count', '', status, 0)
    report.equal(path, 'ffrf_joint_count', '', int(text), len(joints))
    # With near-redundant rows the driver reports the minimum-norm split, flagging every
    # equation it moved by more than 1e-3 of the largest multiplier (src/mbs/reaction_split.f90):
    # the unflagged components are the API's raw ones within 1e-3 of the largest reported
    # reaction of the state; without any flag, bitwise.
    any_flag = any(np.any(driver[f'/joints/{joint}/reaction_min_norm'][row]) for joint in joints)
    reaction_scale = max(float(np.max(np.abs(driver[f'/joints/{joint}/reaction'][row])))
                         for joint in joints) if joints else 0.0
    for j, joint in enumerate(joints):
        report.equal(path, 'ffrf_joint_name', f'joint {j}',
                     value(dump, 'joint_name', str(k), str(j)), (0, joint))
        status, text = value(dump, 'joint_reaction', str(k), str(j))
        report.status(path, 'ffrf_joint_reaction', joint, status, 0)
        fm = numbers(text)
        got = np.concatenate([fm[0:3], fm[6:9], fm[3:6], fm[9:12]])   # driver's row order
        expected = driver[f'/joints/{joint}/reaction'][row]
        flags = driver[f'/joints/{joint}/reaction_min_norm'][row]
        free = flags == 0
        if any_flag:
            report.compare(path, 'ffrf_joint_reaction', f'{joint} state {k} (unflagged)',
                           got[free], expected[free], REACTION_FLAG_RTOL,
                           np.full(int(np.sum(free)), reaction_scale))
        else:
            report.compare(path, 'ffrf_joint_reaction', f'{joint} state {k}', got[free],
                           expected[free])
        if np.any(~free):
            report.notes.append(f'{path}: {joint} at t = {t}: {int(np.sum(~free))} components '
                                f'minimum-norm in the driver\'s file: API (raw multipliers) '
                                f'{got[~free]}, driver {expected[~free]}')
        key = ('reaction components flagged min-norm', path)
        report.worst[key] = (report.worst.get(key, (0, 0, 0))[0] + int(np.sum(~free)), 0, 0)


# The reaction split's flag threshold (CHANGE_RTOL of src/mbs/reaction_split.f90), applied to
# the reaction components (a component is a combination of its joint's equations)
REACTION_FLAG_RTOL = 1e-3


def check_run_output_state(report, dump, driver):
    """After a recorded run: time and crank state are the final ones."""
    path = 'run_output'
    status, text = value(dump, 'mechanism_time', '0')
    report.status(path, 'ffrf_mechanism_time', '', status, 0)
    t, t_end = numbers(text)
    report.compare(path, 'ffrf_mechanism_time', 't', [t], driver['/final_state/t'][()])
    report.compare(path, 'ffrf_mechanism_time', 't (last row)', [t], driver['/time/t'][-1:])
    status, text = value(dump, 'crank_state', '0')
    report.status(path, 'ffrf_crank_state', '', status, 0)
    report.compare(path, 'ffrf_crank_state', 'final', numbers(text),
                   [driver['/time/crank_angle'][-1], driver['/time/crank_speed'][-1]])
    report.compare(path, 'ffrf_crank_state', '/final_state/crank_angle', numbers(text)[:1],
                   driver['/final_state/crank_angle'][()])


def bodies_case(mechanism_file, folder):
    """A modal case of the mechanism's meshed bodies (their resolved &body and &interface
    groups): the driver's /bodies/<b>/mesh and /mass for them."""
    text = mechanism_file['/input/namelist'][()]
    text = text.decode() if isinstance(text, bytes) else str(text)
    lines = ["&run title = 'capi_values: the engine's meshed bodies', "
             "output = 'capi_values_bodies.h5', mode_shapes_msh = 'none' /"]
    meshed = set()
    for line in text.splitlines():
        if line.startswith('&body') and "mesh_file = ''" not in line:
            # mesh and mass do not depend on the modes: one mode each
            lines.append(re.sub(r'num_modes = \d+', 'num_modes = 1', line))
            meshed.add(re.search(r"name = '([^']*)'", line).group(1))
    for line in text.splitlines():
        if line.startswith('&interface') and \
                re.search(r"body = '([^']*)'", line).group(1) in meshed:
            lines.append(line)
        if line.startswith('&modes'):
            lines.append(line)
    path = os.path.join(folder, 'capi_values_bodies.nml')
    with open(path, 'w') as f:
        f.write('\n'.join(lines).replace("'capi_values: the engine's", "'capi_values: engine")
                + '\n')
    return path


def write_arrays(modal, groups, path):
    """The modal case's (single) body as arrays for test_capi_values's path arrays_modal: the
    driver's mesh, material, number of modes and interfaces (node sets with their weights,
    virtual nodes and reference conditions as the driver resolved them)."""
    bodies = [g for n, g in groups if n == 'body']
    if len(bodies) != 1:
        sys.exit('arrays path: the modal case must have one body')
    body = bodies[0]
    name = body['name'][0]
    group = modal['/bodies/' + name]
    xyz = group['mesh/coordinates'][()]
    tets = group['mesh/tets'][()] - 1
    order = [x.decode() for x in group['interfaces/order'][()]]
    weighting = {g['name'][0]: g['weighting'][0] for n, g in groups
                 if n == 'interface' and g['body'][0] == name}
    num_modes = int([g for n, g in groups if n == 'modes'][0]['num_modes'][0])
    lines = [f'{name} {xyz.shape[0]} {tets.shape[1]} {tets.shape[0]} {body["young"][0]} '
             f'{body["poisson"][0]} {body["density"][0]} {num_modes} {len(order)}',
             ' '.join(repr(float(x)) for x in xyz.ravel()),
             ' '.join(str(int(x)) for x in tets.ravel())]
    for interface in order:
        g = group['interfaces/' + interface]
        rc = g['rc_dofs'][()].decode().split()
        nodes = g['nodes'][()] - 1
        weighted = weighting[interface] != 'uniform'
        lines.append(f'{interface} {MPC_CODES[g["mpc"][()].decode()]} {len(nodes)} '
                     f'{int(weighted)} ' + ' '.join(repr(float(x)) for x in g['virtual_node'][()])
                     + ' ' + ' '.join('1' if word in rc else '0' for word in RC_WORDS))
        lines.append(' '.join(str(int(x)) for x in nodes))
        if weighted:
            lines.append(' '.join(repr(float(x)) for x in g['weights'][()]))
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def output_name(case_file):
    for line in open(case_file):
        if line.strip().startswith('&run') and 'output' in line:
            return line.split("output")[1].split("'")[1]
    return os.path.splitext(os.path.basename(case_file))[0] + '.h5'


def main(ffrf, program, modal_case, mechanism_case, mesh_dir, out_dir, chunk):
    start = time.time()
    ffrf, program, modal_case, mechanism_case, mesh_dir, out_dir = map(
        os.path.abspath, (ffrf, program, modal_case, mechanism_case, mesh_dir, out_dir))
    chunk_s = float(chunk)
    driver_dir = os.path.join(out_dir, 'driver')
    # nothing of an earlier run may stand in for this one's files
    for stale in [driver_dir] + [os.path.join(out_dir, p) for p in PATHS]:
        shutil.rmtree(stale, ignore_errors=True)
        if os.path.exists(stale + '.txt'):
            os.remove(stale + '.txt')
    for sub in ('modal', 'mechanism', 'bodies'):
        os.makedirs(os.path.join(driver_dir, sub), exist_ok=True)
    quiet = ['--mesh-dir', mesh_dir, '--quiet']
    run([ffrf, modal_case, '--output-dir', os.path.join(driver_dir, 'modal')] + quiet)
    run([ffrf, mechanism_case, '--output-dir', os.path.join(driver_dir, 'mechanism')] + quiet)
    modal = h5py.File(os.path.join(driver_dir, 'modal', output_name(modal_case)), 'r')
    mechanism = h5py.File(os.path.join(driver_dir, 'mechanism', output_name(mechanism_case)),
                          'r')
    modal_groups = namelist(modal)
    mechanism_groups = namelist(mechanism)
    long_file = os.path.join(driver_dir, 'mechanism', output_name(mechanism_case))
    t_end = float([g for n, g in mechanism_groups if n == 'integrator'][0]['t_end'][0])
    chunks = int(round(t_end / chunk_s))
    velocity_files = [mechanism]
    times = mechanism['/time/t'][()]
    for k in range(1, chunks):
        folder = os.path.join(driver_dir, f't{k}')
        os.makedirs(folder, exist_ok=True)
        # t_end = the driver's own time after k chunks (t_start + n h summed step by step,
        # e.g. 0.0010000000000000002): the run then ends with a full step, as the long run
        # (t_end = 0.001 would shorten the last step by 2e-19 s)
        t_k = times[np.argmin(np.abs(times - k * chunk_s))]
        # the flexible bodies' modes taken from the long run's file (&body modes_file: the
        # same doubles, checked against what they depend on) rather than computed again
        reuse = [item for n, g in mechanism_groups if n == 'body' and g['mesh_file'][0]
                 for item in ('--set', f'body[{g["name"][0]}].modes_file={long_file}')]
        run([ffrf, mechanism_case, '--output-dir', folder, '--set',
             f'integrator.t_end={t_k!r}'] + reuse + quiet)
        velocity_files.append(h5py.File(os.path.join(folder, output_name(mechanism_case)),
                                        'r'))
    bodies_file = bodies_case(mechanism, os.path.join(driver_dir, 'bodies'))
    run([ffrf, bodies_file, '--output-dir', os.path.join(driver_dir, 'bodies')] + quiet)
    bodies = h5py.File(os.path.join(driver_dir, 'bodies', 'capi_values_bodies.h5'), 'r')
    driver_seconds = time.time() - start

    arrays = os.path.join(out_dir, 'arrays.txt')
    write_arrays(modal, modal_groups, arrays)
    run([program, modal_case, mechanism_case, mesh_dir, out_dir, chunk, arrays])
    api_seconds = time.time() - start - driver_seconds
    dumps = {p: read_dump(os.path.join(out_dir, p + '.txt')) for p in PATHS}

    # what is derived here from the driver's meshes, densities and modes
    derived = {}

    def density(groups, name):
        return float([g for n, g in groups if n == 'body' and g['name'][0] == name][0]
                     ['density'][0])

    modal_files, mechanism_files = {}, {}
    for n, g in modal_groups:
        if n == 'body':
            name = g['name'][0]
            group = modal['/bodies/' + name]
            derived[('modal', name)] = Body(group['mesh'], density(modal_groups, name),
                                            group['modes/frequency'][()],
                                            group['modes/shape'][()])
            modal_files[name] = (group, group)
    for n, g in mechanism_groups:
        if n == 'body' and g['mesh_file'][0] != '':
            name = g['name'][0]
            group = mechanism['/bodies/' + name]
            derived[('mechanism', name)] = Body(bodies['/bodies/' + name + '/mesh'],
                                                density(mechanism_groups, name),
                                                group['modes/frequency'][()],
                                                group['modes/shape'][()])
            mechanism_files[name] = (group, bodies['/bodies/' + name])
    for body in derived.values():
        body.invariants_cache = body.invariants()

    report = Report()
    for path in PATHS:
        dump = dumps[path]
        mechanism_path = path.startswith(('chunks', 'run'))
        groups = mechanism_groups if mechanism_path else modal_groups
        kind = 'mechanism' if mechanism_path else 'modal'
        reference = mechanism if mechanism_path else modal
        report.equal(path, 'ffrf_version', '', dump[('version',)][1], version_of(reference))
        check_body_data(report, path, dump, groups,
                        mechanism_files if mechanism_path else modal_files,
                        {name: body for (k, name), body in derived.items() if k == kind})
        if not mechanism_path:
            continue
        states = sorted({int(key[1]) for key in dump if key[0] == 'mechanism_time'})
        if path.startswith('chunks') and len(states) != chunks + 1:
            report.failures.append(f'{path}: {len(states)} states, expected {chunks + 1}')
        if path.startswith('run') and states != [0]:
            report.failures.append(f'{path}: states {states}, expected one')
        if path == 'run_output':
            check_run_output_state(report, dump, mechanism)
        for k in states:
            check_state(report, path, dump, k, mechanism_groups, mechanism, velocity_files)
        if path.startswith('run'):
            # one call to t_end: the state is the final one
            t = numbers(dump[('mechanism_time', '0')][1])[0]
            report.compare(path, 'ffrf_mechanism_time', 'run to t_end', [t],
                           mechanism['/final_state/t'][()])

    # the API's own results files (paths with an output folder) hold the driver's values
    for path, reference, name in (('modal_output', modal, output_name(modal_case)),
                                  ('chunks_output', mechanism, output_name(mechanism_case)),
                                  ('run_output', mechanism, output_name(mechanism_case))):
        with h5py.File(os.path.join(out_dir, path, name), 'r') as written:
            datasets = []
            reference.visititems(lambda key, item: datasets.append(key)
                                 if isinstance(item, h5py.Dataset) and item.dtype.kind == 'f'
                                 and key.startswith(('bodies', 'time', 'joints', 'final_state'))
                                 else None)
            for key in datasets:
                report.compare(path, 'results file (float datasets)', key,
                               written[key][()].ravel(), reference[key][()].ravel())

    # summary: entry point x path, largest difference (in units of the tolerance's scale for
    # a relative tolerance) and the tolerance
    entries = sorted({e for e, _ in report.worst} | {e for e, _ in report.refusals})
    print('largest difference per entry point and path: "bitwise" (tolerance 0), or '
          'difference/scale against the relative tolerance; "status 1": FFRF_BAD_CALL asserted '
          '(rigid bodies: no mesh, no invariants; after a recorded run: no state)')
    print(f'{"entry point":40s} ' + ' '.join(f'{p:>14s}' for p in PATHS))
    for entry in entries:
        cells = []
        for p in PATHS:
            if (entry, p) not in report.worst:
                refused = report.refusals.get((entry, p))
                cells.append(f'{"-" if refused is None else f"status {refused}":>14s}')
                continue
            worst, tolerance, count = report.worst[(entry, p)]
            cells.append(f'{worst:9.2g}/{tolerance:<4.0g}' if tolerance else
                         (f'{worst:>14g}' if entry.startswith('reaction components') else
                          f'{"bitwise" if worst == 0 else f"{worst:.3g}":>14s}'))
        print(f'{entry:40s} ' + ' '.join(cells))
    for note in report.notes:
        print('note:', note)
    print(f'driver runs {driver_seconds:.1f} s, API paths {api_seconds:.1f} s, comparison '
          f'{time.time() - start - driver_seconds - api_seconds:.1f} s')
    if report.failures:
        print('FAILED:\n  ' + '\n  '.join(report.failures[:60]))
        if len(report.failures) > 60:
            print(f'  ... {len(report.failures) - 60} more')
        return 1
    print(f'compare_values: every entry point equals the driver on every path '
          f'({sum(c for _, _, c in report.worst.values())} comparisons)')
    return 0


if __name__ == '__main__':
    if len(sys.argv) != 8:
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
