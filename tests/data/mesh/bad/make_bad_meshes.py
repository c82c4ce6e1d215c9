#!/usr/bin/env python3
"""Write the hand-made bad meshes of tests/regression/mesh_errors.cmake (one defect each).

Run from this folder: python3 make_bad_meshes.py. The files are committed; this script says how
they were made and remakes them (MSH 4.1 ASCII and binary, MSH 2.2 ASCII, Gmsh reference
manual, section "MSH file format"). The valid base: a body "block" of two Tet4 sharing the face
(2, 3, 4), tetrahedra (1, 2, 3, 4) and (2, 3, 4, 5), positively oriented, and the physical
surface "face", triangle (1, 2, 3) on z = 0.
"""
import math
import struct

NODES_PER_TYPE = {2: 3, 4: 4, 5: 8, 6: 6, 7: 5, 9: 6, 11: 10, 15: 1, 1: 2}
DIM_OF_TYPE = {1: 1, 2: 2, 4: 3, 5: 3, 6: 3, 7: 3, 9: 2, 11: 3, 15: 0}

BASE_NODES = [(1, 0.0, 0.0, 0.0), (2, 1.0, 0.0, 0.0), (3, 0.0, 1.0, 0.0), (4, 0.0, 0.0, 1.0),
              (5, 1.0, 1.0, 1.0)]


def base():
    """names: (dim, tag, name); entities: dim -> [(tag, [physical tags])];
    nodes: [(dim, entity, [(tag, x, y, z)])]; elements: [(dim, entity, type, [(tag, nodes)])]"""
    return {
        'names': [(2, 2, 'face'), (3, 1, 'block')],
        'entities': {0: [], 1: [], 2: [(1, [2])], 3: [(1, [1])]},
        'nodes': [(3, 1, list(BASE_NODES))],
        'elements': [(2, 1, 2, [(1, [1, 2, 3])]),
                     (3, 1, 4, [(2, [1, 2, 3, 4]), (3, [2, 3, 4, 5])])],
    }


def counts(mesh):
    node_tags = [n[0] for _, _, block in mesh['nodes'] for n in block]
    elem_tags = [e[0] for _, _, _, block in mesh['elements'] for e in block]
    return node_tags, elem_tags


def fmt(x):
    return repr(float(x)) if math.isfinite(x) else ('nan' if math.isnan(x) else 'inf')


def ascii41(mesh, header=None):
    node_tags, elem_tags = counts(mesh)
    out = ['$MeshFormat', '4.1 0 8', '$EndMeshFormat']
    out += ['$PhysicalNames', str(len(mesh['names']))]
    out += ['%d %d "%s"' % n for n in mesh['names']] + ['$EndPhysicalNames']
    ent = mesh['entities']
    out += ['$Entities', ' '.join(str(len(ent[d])) for d in range(4))]
    for d in range(4):
        for tag, phys in ent[d]:
            box = '0 0 0' if d == 0 else '0 0 0 1 1 1'
            line = '%d %s %d %s' % (tag, box, len(phys), ' '.join(map(str, phys)))
            out.append(line.rstrip() + ('' if d == 0 else ' 0'))
    out.append('$EndEntities')
    h = header or {}
    out += ['$Nodes', '%d %d %d %d' % (len(mesh['nodes']), h.get('num_nodes', len(node_tags)),
                                       h.get('min_node', min(node_tags)),
                                       h.get('max_node', max(node_tags)))]
    for dim, entity, block in mesh['nodes']:
        out.append('%d %d 0 %d' % (dim, entity, len(block)))
        out += [str(n[0]) for n in block]
        out += ['%s %s %s' % tuple(fmt(v) for v in n[1:]) for n in block]
    out.append('$EndNodes')
    out += ['$Elements', '%d %d %d %d' % (len(mesh['elements']),
                                          h.get('num_elements', len(elem_tags)),
                                          min(elem_tags), max(elem_tags))]
    for dim, entity, etype, block in mesh['elements']:
        out.append('%d %d %d %d' % (dim, entity, etype, len(block)))
        out += ['%d %s' % (tag, ' '.join(map(str, nodes))) for tag, nodes in block]
    out.append('$EndElements')
    return '\n'.join(out) + '\n'


def binary41(mesh):
    node_tags, elem_tags = counts(mesh)
    size_t = lambda v: struct.pack('<Q', v)
    i32 = lambda v: struct.pack('<i', v)
    f64 = lambda v: struct.pack('<d', v)
    out = b'$MeshFormat\n4.1 1 8\n' + i32(1) + b'\n$EndMeshFormat\n'
    out += ('$PhysicalNames\n%d\n' % len(mesh['names'])).encode()
    out += ''.join('%d %d "%s"\n' % n for n in mesh['names']).encode() + b'$EndPhysicalNames\n'
    ent = mesh['entities']
    out += b'$Entities\n' + b''.join(size_t(len(ent[d])) for d in range(4))
    for d in range(4):
        for tag, phys in ent[d]:
            out += i32(tag) + b''.join(f64(v) for v in ([0, 0, 0] if d == 0 else [0, 0, 0, 1, 1, 1]))
            out += size_t(len(phys)) + b''.join(i32(p) for p in phys)
            if d > 0:
                out += size_t(0)
    out += b'\n$EndEntities\n'
    out += b'$Nodes\n' + size_t(len(mesh['nodes'])) + size_t(len(node_tags)) + \
        size_t(min(node_tags)) + size_t(max(node_tags))
    for dim, entity, block in mesh['nodes']:
        out += i32(dim) + i32(entity) + i32(0) + size_t(len(block))
        out += b''.join(size_t(n[0]) for n in block)
        out += b''.join(f64(v) for n in block for v in n[1:])
    out += b'\n$EndNodes\n'
    out += b'$Elements\n' + size_t(len(mesh['elements'])) + size_t(len(elem_tags)) + \
        size_t(min(elem_tags)) + size_t(max(elem_tags))
    for dim, entity, etype, block in mesh['elements']:
        out += i32(dim) + i32(entity) + i32(etype) + size_t(len(block))
        out += b''.join(size_t(tag) + b''.join(size_t(v) for v in nodes) for tag, nodes in block)
    out += b'\n$EndElements\n'
    return out


def ascii22(mesh, num_nodes=None):
    """Elements carry (physical, elementary) tags: the first physical group of their entity."""
    phys_of = {(d, tag): phys for d in range(4) for tag, phys in mesh['entities'][d]}
    nodes = [n for _, _, block in mesh['nodes'] for n in block]
    out = ['$MeshFormat', '2.2 0 8', '$EndMeshFormat', '$PhysicalNames',
           str(len(mesh['names']))]
    out += ['%d %d "%s"' % n for n in mesh['names']] + ['$EndPhysicalNames']
    out += ['$Nodes', str(num_nodes if num_nodes is not None else len(nodes))]
    out += ['%d %s %s %s' % ((n[0],) + tuple(fmt(v) for v in n[1:])) for n in nodes]
    out += ['$EndNodes']
    elements = [(tag, etype, phys_of.get((dim, entity), [0])[0], entity, nodes)
                for dim, entity, etype, block in mesh['elements'] for tag, nodes in block]
    out += ['$Elements', str(len(elements))]
    out += ['%d %d 2 %d %d %s' % (tag, etype, phys, entity, ' '.join(map(str, nodes)))
            for tag, etype, phys, entity, nodes in elements]
    out += ['$EndElements']
    return '\n'.join(out) + '\n'


def with_hex(mesh, etype=5):
    """A hexahedron (or prism 6, pyramid 7) in the body's volume entity, beside the
    tetrahedra and sharing their nodes 2, 5 (a half-hex body)."""
    extra = [(6, 2.0, 0.0, 0.0), (7, 2.0, 1.0, 0.0), (8, 1.0, 1.0, 0.0), (9, 1.0, 0.0, 1.0),
             (10, 2.0, 0.0, 1.0), (11, 2.0, 1.0, 1.0)]
    mesh['nodes'][0][2].extend(extra)
    corners = {5: [2, 6, 7, 8, 9, 10, 11, 5], 6: [2, 6, 8, 9, 10, 5], 7: [2, 6, 7, 8, 5]}[etype]
    mesh['elements'].append((3, 1, etype, [(4, corners)]))
    return mesh


def tet10(crack=False):
    """Two Tet10 sharing the face (2, 3, 4); with crack=True the second one has its own
    mid-side node on the shared edge (2, 3), at the same place as the first one's."""
    corners = {n[0]: n[1:] for n in BASE_NODES}
    edges = [(1, 2), (2, 3), (1, 3), (1, 4), (3, 4), (2, 4)]
    nodes = list(BASE_NODES)
    mid = {}

    def midside(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            tag = 6 + len(mid)
            mid[key] = tag
            nodes.append((tag,) + tuple(0.5 * (corners[a][k] + corners[b][k]) for k in range(3)))
        return mid[key]

    tets = []
    for etag, c in ((2, [1, 2, 3, 4]), (3, [2, 3, 4, 5])):
        m = [midside(c[i - 1], c[j - 1]) for i, j in edges]
        tets.append((etag, c + m))
    if crack:
        tag = 6 + len(mid)
        nodes.append((tag,) + tuple(0.5 * (corners[2][k] + corners[3][k]) for k in range(3)))
        second = tets[1][1]
        second[4] = tag                     # edge (2, 3) of tetrahedron (2, 3, 4, 5)
    tri = [1, 2, 3, midside(1, 2), midside(2, 3), midside(1, 3)]
    return {'names': [(2, 2, 'face'), (3, 1, 'block')],
            'entities': {0: [], 1: [], 2: [(1, [2])], 3: [(1, [1])]},
            'nodes': [(3, 1, nodes)],
            'elements': [(2, 1, 9, [(1, tri)]), (3, 1, 11, tets)]}


def write(name, text):
    mode = 'wb' if isinstance(text, bytes) else 'w'
    with open(name, mode) as f:
        f.write(text)


def main():
    write('hex_in_body.msh', ascii41(with_hex(base(), 5)))
    write('prism_in_body_22.msh', ascii22(with_hex(base(), 6)))
    write('pyramid_in_body_bin.msh', binary41(with_hex(base(), 7)))

    m = base()
    m['elements'].insert(0, (1, 1, 200, [(9, [1, 2])]))
    m['entities'][1] = [(1, [])]
    write('unknown_type.msh', ascii41(m))

    m = base()
    m['nodes'][0][2][0] = (0,) + BASE_NODES[0][1:]
    m['elements'] = [(d, e, t, [(tag, [0 if n == 1 else n for n in nodes]) for tag, nodes in b])
                     for d, e, t, b in m['elements']]
    write('node_tag_zero.msh', ascii41(m))
    write('node_tag_zero_22.msh', ascii22(m))

    write('element_count.msh', ascii41(base(), {'num_elements': 4}))
    write('node_range.msh', ascii41(base(), {'max_node': 6}))
    write('node_count_22.msh', ascii22(base(), num_nodes=6))
    text = ascii41(base())
    write('huge_nodes.msh', text.replace('$Nodes\n1 5 1 5\n', '$Nodes\n1 2000000000 1 5\n'))
    write('huge_block.msh', text.replace('3 1 4 2\n', '3 1 4 2000000000\n'))
    write('missing_coordinate.msh', text.replace('\n0.0 1.0 0.0\n', '\n0.0 1.0\n'))
    write('nan_coordinate.msh', text.replace('\n0.0 0.0 1.0\n', '\n0.0 nan 1.0\n'))
    m = base()
    m['nodes'][0][2][3] = (4, 0.0, float('nan'), 1.0)
    write('nan_coordinate_bin.msh', binary41(m))

    m = base()
    m['names'].append((3, 3, 'block'))
    m['entities'][3] = [(1, [1]), (2, [3])]
    write('duplicate_names.msh', ascii41(m))

    m = base()
    m['elements'][1][3].append((4, [2, 1, 4, 3]))
    write('duplicate_tet.msh', ascii41(m))

    m = base()
    m['elements'][0] = (2, 1, 2, [(1, [1, 2, 5])])
    write('not_a_face.msh', ascii41(m))

    m = base()
    m['nodes'][0][2].extend([(6, 3.0, 0.0, 0.0), (7, 4.0, 0.0, 0.0), (8, 3.0, 1.0, 0.0),
                             (9, 3.0, 0.0, 1.0)])
    m['elements'][1][3].append((4, [6, 7, 8, 9]))
    write('two_pieces.msh', ascii41(m))

    m = base()
    m['names'].append((2, 4, 'far'))
    m['entities'][2].append((2, [4]))
    m['entities'][3].append((2, [5]))
    m['names'].append((3, 5, 'other'))
    m['nodes'][0][2].extend([(6, 3.0, 0.0, 0.0), (7, 4.0, 0.0, 0.0), (8, 3.0, 1.0, 0.0),
                             (9, 3.0, 0.0, 1.0)])
    m['elements'].append((2, 2, 2, [(5, [6, 7, 8])]))
    m['elements'].append((3, 2, 4, [(6, [6, 7, 8, 9])]))
    write('surface_outside.msh', ascii41(m))

    m = base()
    m['elements'][1] = (2, 1, 4, m['elements'][1][3])
    write('type_dimension.msh', ascii41(m))

    m = tet10()
    m['elements'][1][3][0][1][4] = 5          # mid-side node of edge (1, 2) := corner 5
    write('tet10_midside_corner.msh', ascii41(m))
    m = tet10()
    m['elements'][1][3][1][1][9] = 6          # edge (3, 5) of the second: the node of edge (1, 2)
    write('tet10_midside_two_edges.msh', ascii41(m))
    write('tet10_ok.msh', ascii41(tet10()))
    write('tet10_crack.msh', ascii41(tet10(crack=True)))
    write('tet10_crack_22.msh', ascii22(tet10(crack=True)))
    write('valid_base.msh', ascii41(base()))
    write('valid_base_bin.msh', binary41(base()))
    write('valid_base_22.msh', ascii22(base()))


if __name__ == '__main__':
    main()
