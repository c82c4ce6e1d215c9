"""Tet10 stiffness and consistent mass of an ffrf body, assembled in numpy, independently of ffrf's
Fortran (for the Exudyn peer of docs/theory.md 4.5; no solver logic of ffrf).

Gmsh node order (docs/method.md "Method and conventions"): corners 0..3, edge nodes 4..9 on the
edges (0,1) (1,2) (0,2) (0,3) (2,3) (1,3). Isoparametric, linear isotropic elasticity. Stiffness
with the 4-point Gauss rule (ffrf's and CalculiX's "full integration"); mass with a collapsed
(Duffy) Gauss product rule of 5^3 points, exact to degree 9 on the reference tetrahedron, so exact
for straight and curved (degree-7 integrand) Tet10 alike.

    K, M = assemble(xyz, tets, young, poisson, density)     # scipy CSR, 3n x 3n, dofs x y z per node
"""
import numpy as np
import scipy.sparse as sp

__all__ = ["assemble", "rigid_inertia"]

EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3))


def _shape(points):
    """N (g, 10) and dN/dxi (g, 10, 3) at reference points (g, 3); L0 = 1 - xi - eta - zeta."""
    xi = np.asarray(points, dtype=float)
    lam = np.column_stack([1.0 - xi.sum(axis=1), xi])            # (g, 4) barycentric
    dlam = np.vstack([-np.ones(3), np.eye(3)])                    # (4, 3) dL_i/dxi
    g = len(xi)
    n = np.empty((g, 10))
    dn = np.empty((g, 10, 3))
    for i in range(4):
        n[:, i] = lam[:, i] * (2.0 * lam[:, i] - 1.0)
        dn[:, i] = (4.0 * lam[:, i] - 1.0)[:, None] * dlam[i]
    for k, (a, b) in enumerate(EDGES):
        n[:, 4 + k] = 4.0 * lam[:, a] * lam[:, b]
        dn[:, 4 + k] = 4.0 * (lam[:, a][:, None] * dlam[b] + lam[:, b][:, None] * dlam[a])
    return n, dn


def _gauss4():
    a, b = 0.5854101966249685, 0.1381966011250105
    pts = np.array([[b, b, b], [a, b, b], [b, a, b], [b, b, a]])
    return pts, np.full(4, 1.0 / 24.0)


def _duffy(order=5):
    """Collapsed Gauss-Legendre product rule on the unit tetrahedron (order^3 points)."""
    x, w = np.polynomial.legendre.leggauss(order)
    x = 0.5 * (x + 1.0)
    w = 0.5 * w
    u, v, s = np.meshgrid(x, x, x, indexing="ij")
    wu, wv, ws = np.meshgrid(w, w, w, indexing="ij")
    xi = u
    eta = v * (1.0 - u)
    zeta = s * (1.0 - u) * (1.0 - v)
    weight = wu * wv * ws * (1.0 - u) ** 2 * (1.0 - v)
    return np.column_stack([xi.ravel(), eta.ravel(), zeta.ravel()]), weight.ravel()


def _jacobians(xe, dn):
    """J (e, g, 3, 3) = dx/dxi and det J (e, g) for element coordinates xe (e, 10, 3)."""
    jac = np.einsum("eai,gaj->egij", xe, dn, optimize=True)
    return jac, np.linalg.det(jac)


def assemble(xyz, tets, young, poisson, density):
    """K and M (scipy CSR, 3n x 3n) of a Tet10 mesh: xyz (n, 3), tets (e, 10) 0-based."""
    xyz = np.asarray(xyz, dtype=float)
    tets = np.asarray(tets, dtype=np.int64)
    xe = xyz[tets]
    num_dofs = 3 * len(xyz)
    dofs = (3 * tets[:, :, None] + np.arange(3)).reshape(len(tets), 30)
    rows = np.repeat(dofs, 30, axis=1).ravel()
    cols = np.tile(dofs, (1, 30)).ravel()

    # stiffness: B (e, g, 6, 30) with engineering shear strains, Voigt xx yy zz yz xz xy
    lam = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))
    mu = young / (2.0 * (1.0 + poisson))
    d = np.zeros((6, 6))
    d[:3, :3] = lam
    d[np.arange(3), np.arange(3)] += 2.0 * mu
    d[np.arange(3, 6), np.arange(3, 6)] = mu
    pts, wts = _gauss4()
    _, dn = _shape(pts)
    jac, det = _jacobians(xe, dn)
    if np.any(det <= 0.0):
        raise ValueError(f"{np.count_nonzero(det <= 0.0)} Gauss points with det J <= 0 (inverted Tet10)")
    dndx = np.einsum("gaj,egji->egai", dn, np.linalg.inv(jac), optimize=True)   # (e, g, 10, 3)
    e, g = det.shape
    b = np.zeros((e, g, 6, 10, 3))
    for i in range(3):
        b[:, :, i, :, i] = dndx[:, :, :, i]
    b[:, :, 3, :, 1] = dndx[:, :, :, 2]
    b[:, :, 3, :, 2] = dndx[:, :, :, 1]
    b[:, :, 4, :, 0] = dndx[:, :, :, 2]
    b[:, :, 4, :, 2] = dndx[:, :, :, 0]
    b[:, :, 5, :, 0] = dndx[:, :, :, 1]
    b[:, :, 5, :, 1] = dndx[:, :, :, 0]
    b = b.reshape(e, g, 6, 30)
    ke = np.einsum("egia,ij,egjb,eg->eab", b, d, b, det * wts, optimize=True)
    stiffness = sp.csr_matrix((ke.ravel(), (rows, cols)), shape=(num_dofs, num_dofs))

    # consistent mass: rho N_a N_b I3
    pts, wts = _duffy(5)
    n, dn = _shape(pts)
    _, det = _jacobians(xe, dn)
    me = density * np.einsum("ga,gb,eg->eab", n, n, det * wts, optimize=True)     # (e, 10, 10)
    me3 = np.zeros((e, 10, 3, 10, 3))
    for i in range(3):
        me3[:, :, i, :, i] = me
    mass = sp.csr_matrix((me3.reshape(e, 30, 30).ravel(), (rows, cols)),
                         shape=(num_dofs, num_dofs))
    return stiffness, mass


def rigid_inertia(xyz, mass_matrix):
    """Mass, centre of mass and inertia tensor about it from the consistent mass matrix
    (theory.md 3.2): m = 1^T M_x 1, chi = sum M x / m, J = int rho (|r|^2 I - r r^T)."""
    xyz = np.asarray(xyz, dtype=float)
    mx = mass_matrix[0::3, 0::3]                                   # scalar mass matrix
    m = mx.sum()
    chi = (mx @ xyz).sum(axis=0) / m
    r = xyz - chi
    second = r.T @ (mx @ r)                                        # int rho r r^T
    inertia = np.trace(second) * np.eye(3) - second
    return m, chi, inertia
