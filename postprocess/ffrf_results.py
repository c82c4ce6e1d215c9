"""Read an ffrf results file (HDF5, one per run) with h5py.

Only reading and reshaping: no solver logic. Layout (see the README, "Results file"): the
Fortran writer stores arrays in Fortran order, so h5py sees them transposed, e.g.
/bodies/<body>/mesh/coordinates as (num_nodes, 3) and /bodies/<body>/modes/shape as
(num_modes, 3*num_nodes). Strings are fixed-length and come back as bytes; `text` decodes.

    with ffrf_results.open_results("crank_rc1.h5") as results:
        body = results.bodies()[0]
        hz = results.frequencies(body)
        u = results.shapes(body)               # (num_modes, num_nodes, 3)
        tris = results.surface_triangles(body)  # (num_triangles, 3), 0-based, outward
"""
import h5py
import numpy as np

__all__ = ["ResultsError", "Results", "open_results", "text", "exterior_faces"]


class ResultsError(Exception):
    """A results file that cannot be used: missing, failed run, missing dataset."""


def text(value):
    """A str from what h5py returns for a string dataset or attribute (bytes, numpy bytes,
    str, or a 0-d array of those)."""
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).rstrip(b"\0").decode("utf-8", errors="replace")
    return str(value)


def exterior_faces(tets, xyz=None):
    """Exterior triangles of a tetrahedral mesh: the faces that belong to one tetrahedron only.

    tets: (num_tets, nen) 0-based node indices, corners first (Gmsh order, nen 4 or 10; only the
    4 corners are used). xyz: (num_nodes, 3) coordinates; when given, the triangles are ordered
    so that their normals (p1 - p0) x (p2 - p0) point out of the mesh. Returns (num_faces, 3).
    """
    corners = np.asarray(tets)[:, :4].astype(np.int64)
    if xyz is not None:
        p = np.asarray(xyz, dtype=float)[corners]
        volume6 = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]),
                            p[:, 3] - p[:, 0])
        negative = volume6 < 0.0
        corners = corners.copy()
        corners[negative, 1], corners[negative, 2] = corners[negative, 2], corners[negative, 1]
    # outward faces of a positively oriented tetrahedron (a, b, c, d): each face seen from
    # outside is counter-clockwise
    a, b, c, d = corners.T
    faces = np.concatenate([np.stack(f, axis=1) for f in
                            ((a, c, b), (a, b, d), (a, d, c), (b, c, d))])
    keys = np.sort(faces, axis=1)
    _, first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
    return faces[np.sort(first[counts == 1])]


class Results:
    """One open results file. Raises ResultsError unless the run's status is 'complete'
    (pass require_complete=False to look at a failed run)."""

    def __init__(self, path, require_complete=True):
        self.path = str(path)
        try:
            self.file = h5py.File(self.path, "r")
        except OSError as exc:
            raise ResultsError(f"{self.path}: cannot open as HDF5 ({exc})") from exc
        self.status = text(self.file.attrs.get("status", b"(no status attribute)"))
        if require_complete and self.status != "complete":
            self.file.close()
            raise ResultsError(f"{self.path}: the run did not complete, status is "
                               f"'{self.status}'; rerun it or look at its log")

    def close(self):
        self.file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _dataset(self, path):
        if path not in self.file:
            raise ResultsError(f"{self.path}: no dataset {path}")
        return self.file[path][()]

    def attribute(self, name, path="/", default=None):
        """A string or number attribute of `path` (strings decoded)."""
        if path not in self.file:
            return default
        value = self.file[path].attrs.get(name, default)
        if isinstance(value, (bytes, np.bytes_, str)):
            return text(value)
        return value

    @property
    def case_name(self):
        return self.attribute("case_name", default="")

    def bodies(self):
        """Names of the bodies in the file, in stored (alphabetical) order."""
        if "bodies" not in self.file:
            return []
        return list(self.file["bodies"].keys())

    def body(self, name=None):
        """`name` if the file has it, else the first body; ResultsError if none or unknown."""
        names = self.bodies()
        if not names:
            raise ResultsError(f"{self.path}: no bodies in the file")
        if name is None:
            return names[0]
        if name not in names:
            raise ResultsError(f"{self.path}: no body '{name}'; bodies: {', '.join(names)}")
        return name

    def frequencies(self, body):
        """Natural frequencies, Hz, (num_modes,)."""
        return np.atleast_1d(self._dataset(f"/bodies/{body}/modes/frequency")).astype(float)

    def shapes(self, body):
        """Mass-normalised mode shapes as (num_modes, num_nodes, 3)."""
        shape = np.atleast_2d(self._dataset(f"/bodies/{body}/modes/shape")).astype(float)
        return shape.reshape(shape.shape[0], -1, 3)

    def coordinates(self, body):
        """Node coordinates, m, (num_nodes, 3)."""
        return self._dataset(f"/bodies/{body}/mesh/coordinates").astype(float)

    def tets(self, body):
        """Tetrahedra as 0-based node indices, (num_tets, 4 or 10)."""
        return self._dataset(f"/bodies/{body}/mesh/tets").astype(np.int64) - 1

    def surface_triangles(self, body):
        """Exterior triangles (corner nodes, 0-based, outward normals), (num_triangles, 3)."""
        return exterior_faces(self.tets(body), self.coordinates(body))

    def modes_info(self, body):
        """The modes group's attributes: rc_set, mpc, formulation (strings, '' if absent)."""
        path = f"/bodies/{body}/modes"
        return {key: self.attribute(key, path, default="")
                for key in ("rc_set", "mpc", "formulation")}

    def label(self, body):
        """'RC set 1, RBE3' from the modes attributes (the file name if they are absent)."""
        info = self.modes_info(body)
        parts = [p for p in (info["rc_set"], info["mpc"]) if p]
        return ", ".join(parts) if parts else self.path


def open_results(path, require_complete=True):
    """Open a results file (context manager); see Results."""
    return Results(path, require_complete=require_complete)
