#!/usr/bin/env python3
"""Read an ffrf XDMF export (&run export = 'xdmf') back with meshio and check it against the
HDF5 results file it points into (docs/results.md "XDMF export").

Each top-level grid of the Domain (one per flexible body) is copied into a one-grid XDMF file
beside the original (meshio reads one grid per file), and meshio reads it:
  - a modal run (Uniform grid): the points equal /bodies/<b>/mesh/coordinates bitwise, the cells
    equal /bodies/<b>/mesh/tets in VTK's order, 0-based (Gmsh's Tet10 with its last two nodes
    swapped), exactly, and mode k's point vectors equal column k of /bodies/<b>/modes/shape
    bitwise, for every mode;
  - a mechanism run without frames (Uniform grid, no /bodies/<b>/mesh): the points equal
    /xdmf/<b>/geometry bitwise and it has no fields;
  - a mechanism run (Temporal collection): every frame's "elastic displacement" equals the
    dataset /xdmf/<b>/frame_<k> bitwise, its time is one of /time/t exactly, the number of
    frames is --frames, and (--animation BODY=FILE) each frame equals the Gmsh animation's
    time step of the same index (written with 7 significant digits: 1e-6 of the largest value)
    at the same time (17 digits: bitwise).
  - node order, geometrically (every body): each mid-edge node of a Tet10 is the midpoint of
    its edge's corner nodes in VTK's edge order (0,1) (1,2) (2,0) (0,3) (1,3) (2,3) to 1e-12
    of the edge length (measured: 1.3e-14 at most), except on boundary edges, where Gmsh puts
    the node on the curved surface: there within a quarter of the edge length (measured: 0.053
    on the crank, 0.116 on the conrod at lc = 8 mm), a node on another edge of the element being
    about half an edge away; the check fails for Gmsh's own order (run on the cells with nodes 8
    and 9 swapped back), so it is not vacuous.
Exit status 1 with the failures listed.
"""
import argparse
import pathlib
import sys
import xml.etree.ElementTree as ET

import h5py
import meshio
import meshio.xdmf
import numpy as np

VTK_TET10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
MIDPOINT_RTOL = 1.0e-12
BOUNDARY_SAGITTA = 0.25
GMSH_FRAME_RTOL = 1.0e-6


def boundary_edges(cells):
    """Sorted corner pairs of the edges of faces that belong to one tetrahedron only."""
    corners = cells[:, :4]
    faces = np.concatenate([corners[:, [0, 1, 2]], corners[:, [0, 1, 3]],
                            corners[:, [0, 2, 3]], corners[:, [1, 2, 3]]])
    faces = np.sort(faces, axis=1)
    unique, counts = np.unique(faces, axis=0, return_counts=True)
    outer = unique[counts == 1]
    pairs = np.concatenate([outer[:, [0, 1]], outer[:, [1, 2]], outer[:, [0, 2]]])
    return {tuple(p) for p in pairs}


def midpoint_failures(points, cells):
    """Mid-edge nodes off their edge's midpoint (module notes); 0 for Tet4."""
    if cells.shape[1] != 10:
        return 0
    outer = boundary_edges(cells)
    failures = 0
    for e, (a, b) in enumerate(VTK_TET10_EDGES):
        pa, pb, mid = points[cells[:, a]], points[cells[:, b]], points[cells[:, 4 + e]]
        length = np.linalg.norm(pb - pa, axis=1)
        off = np.linalg.norm(mid - 0.5 * (pa + pb), axis=1) / length
        on_boundary = np.array([(min(i, j), max(i, j)) in outer
                                for i, j in zip(cells[:, a], cells[:, b])])
        limit = np.where(on_boundary, BOUNDARY_SAGITTA, MIDPOINT_RTOL)
        failures += int(np.count_nonzero(off > limit))
    return failures


def gmsh_frames(path):
    """(times, values) of the $NodeData blocks of a Gmsh MSH 2.2 animation."""
    lines = pathlib.Path(path).read_text().splitlines()
    times, frames, i = [], [], 0
    while i < len(lines):
        if lines[i] == '$NodeData':
            num_strings = int(lines[i + 1])
            j = i + 2 + num_strings
            times.append(float(lines[j + 1]))
            j += 2
            num_ints = int(lines[j])
            num_nodes = int(lines[j + 3])
            j += 1 + num_ints
            rows = [line.split() for line in lines[j:j + num_nodes]]
            frames.append(np.array([[float(v) for v in r[1:]] for r in rows]))
            i = j + num_nodes
        i += 1
    return times, frames


def one_grid_file(xdmf, grid, name):
    """A copy of `xdmf` holding grid `grid` alone, in the same folder (relative HDF5 paths)."""
    root = ET.Element('Xdmf', Version='3.0')
    domain = ET.SubElement(root, 'Domain')
    domain.append(grid)
    path = xdmf.with_name(xdmf.stem + '.check_' + name + '.xdmf')
    ET.ElementTree(root).write(path)
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('xdmf', type=pathlib.Path)
    parser.add_argument('--bodies', type=int, required=True, help='top-level grids expected')
    parser.add_argument('--frames', type=int, default=0, help='frames per body (mechanism)')
    parser.add_argument('--animation', action='append', default=[], metavar='BODY=FILE')
    args = parser.parse_args()
    animations = dict(a.split('=', 1) for a in args.animation)
    failures = []

    def check(what, ok):
        print(('ok   ' if ok else 'FAIL ') + what)
        if not ok:
            failures.append(what)

    tree = ET.parse(args.xdmf)
    check('XDMF version 3', tree.getroot().get('Version', '').startswith('3'))
    grids = list(tree.getroot().find('Domain'))
    check(f'{len(grids)} body grids, {args.bodies} expected', len(grids) == args.bodies)
    item = tree.getroot().find('.//DataItem')
    h5 = h5py.File(args.xdmf.parent / item.text.split(':')[0].strip(), 'r')
    for grid in grids:
        name = grid.get('Name')
        copy = one_grid_file(args.xdmf, grid, name)
        try:
            if grid.get('GridType') == 'Uniform' and f'/bodies/{name}/mesh' not in h5:
                # a mechanism run without frames: the mesh alone
                mesh = meshio.read(copy, file_format='xdmf')
                points, blocks = mesh.points, mesh.cells
                check(f'{name}: points = /xdmf/{name}/geometry (bitwise), no fields',
                      np.array_equal(points, h5[f'/xdmf/{name}/geometry'][()])
                      and not mesh.point_data and args.frames == 0)
            elif grid.get('GridType') == 'Uniform':
                mesh = meshio.read(copy, file_format='xdmf')
                points, blocks = mesh.points, mesh.cells
                check(f'{name}: points = /bodies/{name}/mesh/coordinates (bitwise)',
                      np.array_equal(points, h5[f'/bodies/{name}/mesh/coordinates'][()]))
                tets = h5[f'/bodies/{name}/mesh/tets'][()]
                if tets.shape[1] == 10:
                    tets = tets[:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]]
                check(f'{name}: cells = Gmsh tets in VTK order, 0-based',
                      len(blocks) == 1 and np.array_equal(blocks[0].data, tets - 1))
                shape = h5[f'/bodies/{name}/modes/shape'][()]
                modes = {int(k.split()[1].rstrip(',')): v for k, v in mesh.point_data.items()}
                check(f'{name}: {len(modes)} modes, {shape.shape[0]} in the results',
                      sorted(modes) == list(range(1, shape.shape[0] + 1)))
                check(f'{name}: every mode = /bodies/{name}/modes/shape (bitwise)',
                      all(np.array_equal(modes[k], shape[k - 1].reshape(-1, 3))
                          for k in modes))
            else:
                with meshio.xdmf.TimeSeriesReader(copy) as reader:
                    points, blocks = reader.read_points_cells()
                    frames = [reader.read_data(k) for k in range(reader.num_steps)]
                check(f'{name}: points = /xdmf/{name}/geometry (bitwise)',
                      np.array_equal(points, h5[f'/xdmf/{name}/geometry'][()]))
                check(f'{name}: cells = /xdmf/{name}/topology',
                      len(blocks) == 1 and np.array_equal(blocks[0].data,
                                                          h5[f'/xdmf/{name}/topology'][()]))
                check(f'{name}: {len(frames)} frames, {args.frames} expected',
                      len(frames) == args.frames)
                t_all = h5['/time/t'][()]
                check(f'{name}: every frame = /xdmf/{name}/frame_k (bitwise), at a step time',
                      all(np.array_equal(pd['elastic displacement'],
                                         h5[f'/xdmf/{name}/frame_{k + 1}'][()])
                          and t in t_all for k, (t, pd, _) in enumerate(frames)))
                if name in animations:
                    times, values = gmsh_frames(animations[name])
                    scale = max(np.abs(v).max() for v in values)
                    check(f'{name}: frame times = the Gmsh animation\'s (bitwise)',
                          times == [t for t, _, _ in frames])
                    check(f'{name}: frames = the Gmsh animation\'s to {GMSH_FRAME_RTOL} of '
                          f'{scale:.3g} m', len(values) == len(frames) and all(
                              np.abs(pd['elastic displacement'] - v).max()
                              <= GMSH_FRAME_RTOL * scale
                              for (_, pd, _), v in zip(frames, values)))
            cells = blocks[0].data
            check(f'{name}: mid-edge nodes at their VTK edges\' midpoints',
                  midpoint_failures(points, cells) == 0)
            if cells.shape[1] == 10:
                gmsh_order = cells[:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]]
                check(f'{name}: the same check fails for Gmsh\'s order (not vacuous)',
                      midpoint_failures(points, gmsh_order) > 0)
        finally:
            copy.unlink()
    if failures:
        sys.exit(f'check_xdmf: {len(failures)} failure(s)')


if __name__ == '__main__':
    main()
