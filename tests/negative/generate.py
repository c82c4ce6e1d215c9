#!/usr/bin/env python3
"""Generate the negative suite: mutated Gmsh meshes and namelist cases, each with its verdict.

    generate.py --base-dir DIR --input-dir input --out OUT [--class msh41|msh41_binary|msh22|namelist]

--base-dir holds the gmsh-made base meshes fuzz_block_{tet4,tet10}_{msh41,msh41_binary,msh22}.msh
(input/fuzz_block.geo, see negative.cmake); --input-dir the case files input/*.nml (those with a
&body group; study.nml is not a driver case). Everything is deterministic: each input comes from
random.Random('<class>:<index>') and the base files, so OUT is the same on every machine.

OUT/<class>/manifest.json lists, per generated input: id, case (the case file to run), target (the
mutated file, whose base name the error line must carry), mutation, expected (the allowed exit
codes), names (strings the one error line must contain), key_names (group and key it must also
contain when the exit code is 2, an input error) and mesh_dir (true: run with --mesh-dir).

VERDICT RULES (exit codes of the driver: 0 ok, 2 bad input, 3 file, 4 numerical failure):
  * Invalid by construction -> one exact code, 2: every content error of a mesh or a case (node tag
    0, counts that disagree with the data or with the file's size, unknown or non-tetrahedral
    elements in the body's volume, duplicate/inverted/degenerate tetrahedra, a cracked Tet10, an
    interface triangle that is no face of a tetrahedron, a body in two pieces, duplicate or missing
    physical names, a missing/duplicated/misspelled section, a bad MeshFormat line, NaN/Inf/1e999
    anywhere a real goes, an empty or binary-garbage file; in a case: wrong types ('steel' for a
    real, 1.5 for an integer, .maybe. for a logical), non-finite reals, out-of-range values named
    by the issue, repeated keys, a repeated single group, an unclosed group, text after '/', an
    unknown key or group, no &body, a repeated dof, outputs leaving --output-dir).
    Exit 3 where a named file is not a regular file (/dev/zero, a folder, a FIFO as case, mesh or
    table file). The values issue 10 lists (h = Inf or 1e300, t_end = Inf, gravity = NaN,
    stall_torque = NaN, crank_angle_deg = 1e300, young/density = Inf, a NaN position) -> 2 naming
    the group and key.
  * Plausible but undecided -> a set: huge finite coordinates (+-1e308) {2, 4} (refused as input or
    overflowing in the element matrices); huge finite values of keys without a documented bound,
    missing optional groups {0, 2, 4}; reordered sections, trailing garbage after the last section,
    very long lines or names, element tag 0 or repeated element tags {0, 2}; a mesh path whose
    first 256 characters name an existing mesh {2, 3} (too long, or not found: never read cut).
  * Random mutations (truncation, bit flips, byte overwrites, line deletion/duplication, swapped
    lines) that may or may not stay valid -> {0, 2, 3, 4}: never 1, never a signal.
  * Positive controls (unchanged copy, sparse huge node tags, reversed node blocks, reordered
    groups, a comment after '/') -> {0}.
Every non-zero exit must print exactly one stderr line 'ffrf: error: ...' containing the mutated
file's base name (mesh mutations: the .msh; case mutations: the .nml, plus, for exit 2, the group
and key where the mutation has one; a mutated path value: that path's base name instead).
"""
import argparse
import json
import os
import random
import re
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mshfile import MeshFile, TET_TYPES, TRI_TYPES  # noqa: E402

MESH_CLASSES = ('msh41', 'msh41_binary', 'msh22')
BASE_ORDERS = ('tet4', 'tet10')
RANDOM = [0, 2, 3, 4]
#: inputs per mesh class (deterministic mutations of both bases first, then random ones)
MESHES_PER_CLASS = 300

#: the modal case around every mutated mesh: face_a clamped, face_b free, face_c unused
MESH_CASE = """&body name = 'block', mesh_file = '{mesh}', volumes = 'block',
      young = 210.0e9, poisson = 0.3, density = 7850.0 /
&interface body = 'block', name = 'face_a', rc = 'Tx Ty Tz Rx Ry Rz' /
&interface body = 'block', name = 'face_b', rc = '' /
&modes num_modes = 4 /
"""


# ====================================================================== meshes
def tets(m):
    return [(b, i, t, nodes) for b, i, t, nodes in m.elements() if t in TET_TYPES]


def face_triangles(m, axis, value):
    """Triangles whose vertices all lie on the plane coordinate[axis] == value."""
    xyz = m.coordinates()
    return [(b, i, t, nodes) for b, i, t, nodes in m.elements()
            if t in TRI_TYPES and all(abs(xyz[n][axis] - value) < 1e-9 for n in nodes[:3])]


def interior_tet(m, rng):
    """A tetrahedron with no vertex on the block's boundary (else any tetrahedron)."""
    xyz = m.coordinates()
    box = ((0.0, 0.040), (0.0, 0.020), (0.0, 0.020))

    def inside(n):
        return all(lo + 1e-9 < xyz[n][a] < hi - 1e-9 for a, (lo, hi) in enumerate(box))
    all_tets = tets(m)
    inner = [t for t in all_tets if any(inside(n) for n in t[3][:4])]
    return rng.choice(inner or all_tets)


def rename_node(m, old, new):
    for b in m.node_blocks:
        b.tags = [new if t == old else t for t in b.tags]
    for b, i, _, nodes in list(m.elements()):
        if old in nodes:
            m.set_element_nodes(b, i, [new if n == old else n for n in nodes])


def set_coordinate(m, rng, value):
    b, i, t, nodes = interior_tet(m, rng)
    tag = nodes[0]
    for nb, k, ntag, _ in m.nodes():
        if ntag == tag:
            nb.coords[k][rng.randrange(3)] = value if m.fmt != 'msh41_binary' else float(value)
    return 'node %d' % tag


def replace_physical_name(m, old, new):
    text = m.section_text('PhysicalNames')
    m.set_section_text('PhysicalNames', text.replace('"%s"' % old, '"%s"' % new))


def mesh_mutations(fmt, order):
    """(name, expected codes, function(mesh, rng) -> mesh or bytes) of the deterministic mutations."""
    binary = fmt == 'msh41_binary'
    ascii_ = not binary
    v41 = fmt != 'msh22'
    tet10 = order == 'tet10'
    out = []

    def add(name, expected, func, when=True):
        if when:
            out.append((name, expected, func))

    # --- positive controls
    add('unchanged', [0], lambda m, r: m)

    def sparse_tags(m, r):
        mapping = {t: t * 1000003 + 10**12 for _, _, t, _ in m.nodes()}
        for b in m.node_blocks:
            b.tags = [mapping[t] for t in b.tags]
        for b, i, _, nodes in list(m.elements()):
            m.set_element_nodes(b, i, [mapping[n] for n in nodes])
        m.fix_headers()
        return m
    add('sparse_huge_node_tags', [0], sparse_tags)

    def reversed_nodes(m, r):
        for b in m.node_blocks:
            b.tags.reverse()
            b.coords.reverse()
        return m
    add('reversed_node_order', [0], reversed_nodes)

    # --- node tags
    def node_tag(value):
        def f(m, r):
            tag = interior_tet(m, r)[3][0]
            rename_node(m, tag, value)
            if v41:
                m.fix_headers()
            return m
        return f
    add('node_tag_0', [2], node_tag(0))
    add('node_tag_negative', [2], node_tag(-7), ascii_)
    add('node_tag_2pow64_minus_1', [2], node_tag(2**64 - 1), binary)
    add('node_tag_huge_1e30', [2], node_tag(10**30), ascii_)

    def node_tag_unfixed(value):
        def f(m, r):                 # tag and references changed, header min/max left as they were
            rename_node(m, interior_tet(m, r)[3][0], value)
            return m
        return f
    add('node_tag_2pow63_header_unchanged', [2], node_tag_unfixed(2**63 + 235))
    add('node_tag_2pow62_header_unchanged', [2], node_tag_unfixed(2**62 + 235))

    def tags_span_2pow63(m, r):
        # node tags (elements unchanged) whose difference overflows a signed 64-bit integer, as
        # a random overwrite of binary tags made them: SIGSEGV in the reader's tag map, 2026-11-25
        values = [13598769707938218218, 7031476716390354924, 415506398899]
        b = max(m.node_blocks, key=lambda blk: len(blk.tags))
        k = r.randrange(len(b.tags) - 3)
        b.tags[k:k + 3] = values
        return m
    add('node_tags_span_over_2pow63', [2], tags_span_2pow63, binary)

    def node_tag_text(m, r):
        tag = interior_tet(m, r)[3][0]
        for b in m.node_blocks:
            b.tags = ['7x' if t == tag else t for t in b.tags]
        return m
    add('node_tag_not_a_number', [2], node_tag_text, ascii_)

    def duplicate_node_tag(m, r):
        a, b_ = interior_tet(m, r)[3][:2]
        for blk in m.node_blocks:
            blk.tags = [a if t == b_ else t for t in blk.tags]
        if v41:
            m.fix_headers()
        return m
    add('duplicate_node_tag', [2], duplicate_node_tag)

    # --- element node references
    def element_node(value_of):
        def f(m, r):
            b, i, t, nodes = interior_tet(m, r)
            nodes = list(nodes)
            nodes[r.randrange(len(nodes))] = value_of(m)
            m.set_element_nodes(b, i, nodes)
            return m
        return f
    add('element_names_missing_node', [2], element_node(lambda m: m.max_node_tag() + 1000))
    add('element_names_node_0', [2], element_node(lambda m: 0))

    # --- counts
    def count(section, field, delta=None, value=None):
        def f(m, r):
            header = m.node_header if section == 'Nodes' else m.elem_header
            header[field] = value if value is not None else header[field] + delta
            return m
        return f
    total = 1 if v41 else 0
    add('num_nodes_plus_1', [2], count('Nodes', total, +1))
    add('num_nodes_minus_1', [2], count('Nodes', total, -1))
    add('num_elements_plus_1', [2], count('Elements', total, +1))
    add('num_elements_minus_1', [2], count('Elements', total, -1))
    add('num_nodes_1e12', [2], count('Nodes', total, value=10**12))
    add('num_elements_2pow62', [2], count('Elements', total, value=2**62))
    add('num_nodes_negative', [2], count('Nodes', total, value=-5), ascii_)
    add('num_node_blocks_plus_1', [2], count('Nodes', 0, +1), v41)
    add('num_element_blocks_minus_1', [2], count('Elements', 0, -1), v41)

    def block_count(section, delta=None, value=None):
        def f(m, r):
            blocks = m.node_blocks if section == 'Nodes' else m.elem_blocks
            b = max(blocks, key=lambda blk: blk.header[3])
            b.header[3] = value if value is not None else b.header[3] + delta
            return m
        return f
    add('node_block_count_plus_1', [2], block_count('Nodes', +1), v41)
    add('node_block_count_minus_1', [2], block_count('Nodes', -1), v41)
    add('element_block_count_plus_1', [2], block_count('Elements', +1), v41)
    add('element_block_count_1e15', [2], block_count('Elements', value=10**15), v41)

    # --- element types and shapes in the body's volume
    def add_volume_element(element_type, num):
        def f(m, r):
            pool = []
            for _, _, _, nodes in tets(m):
                pool += [n for n in nodes[:4] if n not in pool]
            m.add_element(element_type, pool[:num])
            return m
        return f
    add('unknown_type_99_in_volume', [2], add_volume_element(99, 4), ascii_)
    add('unknown_type_99_in_volume', [2], add_volume_element(99, 4), binary)
    add('hexahedron_in_volume', [2], add_volume_element(5, 8))
    add('prism_in_volume', [2], add_volume_element(6, 6))
    add('pyramid_in_volume', [2], add_volume_element(7, 5))
    def tet10_in_tet4(m, r):
        nodes = list(interior_tet(m, r)[3][:4])
        xyz = m.coordinates()
        edges = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)]
        mids = [[(xyz[nodes[a]][k] + xyz[nodes[b]][k]) / 2 for k in range(3)] for a, b in edges]
        m.add_element(11, nodes + m.add_nodes(mids))
        return m
    if tet10:
        add('tet4_in_tet10_mesh', [2], add_volume_element(4, 4))
    else:
        add('tet10_in_tet4_mesh', [2], tet10_in_tet4)

    def duplicate_tet(m, r):
        _, _, t, nodes = interior_tet(m, r)
        m.add_element(t, list(nodes))
        return m
    add('duplicate_tetrahedron', [2], duplicate_tet)

    def inverted_tet(m, r):
        b, i, t, nodes = interior_tet(m, r)
        n = list(nodes)
        n[0], n[1] = n[1], n[0]
        if t == 11:                  # keep the edges with their vertices: 5<->6, 7<->9
            n[5], n[6] = n[6], n[5]
            n[7], n[9] = n[9], n[7]
        m.set_element_nodes(b, i, n)
        return m
    add('inverted_tetrahedron', [2], inverted_tet)

    def degenerate_tet(m, r):
        b, i, t, nodes = interior_tet(m, r)
        n = list(nodes)
        n[3] = n[0]
        m.set_element_nodes(b, i, n)
        return m
    add('degenerate_tetrahedron_repeated_node', [2], degenerate_tet)

    def cracked_tet10(m, r):
        b, i, t, nodes = interior_tet(m, r)
        n = list(nodes)
        xyz = m.coordinates()
        n[4] = m.add_nodes([xyz[n[4]]])[0]     # a copy of mid-side node 5, not shared
        m.set_element_nodes(b, i, n)
        return m
    add('tet10_midside_node_not_shared', [2], cracked_tet10, tet10)

    def second_piece(m, r):
        corners = [(0.1, 0, 0), (0.11, 0, 0), (0.1, 0.01, 0), (0.1, 0, 0.01)]
        if tet10:
            edges = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)]
            corners += [tuple((corners[a][k] + corners[b][k]) / 2 for k in range(3))
                        for a, b in edges]
        m.add_element(11 if tet10 else 4, m.add_nodes(corners))
        return m
    add('body_in_two_pieces', [2], second_piece)

    def triangle_not_a_face(m, r):
        b, i, t, nodes = r.choice(face_triangles(m, 0, 0.0))
        n = list(nodes)
        xyz = m.coordinates()
        far = max(xyz, key=lambda tag: xyz[tag][0])       # a node on face_b
        n[0] = far
        m.set_element_nodes(b, i, n)
        return m
    add('interface_triangle_not_a_face', [2], triangle_not_a_face)

    def element_tag(value_of):
        def f(m, r):
            b, i, t, nodes = interior_tet(m, r)
            b.elems[i][0] = value_of(m)
            return m
        return f
    add('element_tag_0', [0, 2], element_tag(lambda m: 0))
    add('element_tag_repeated', [0, 2], element_tag(lambda m: 1))

    # --- coordinates
    for text in ('nan', 'inf', '-inf', '1e999', 'NaN', '-1e999'):
        if binary and text in ('NaN', '1e999', '-1e999'):
            continue
        add('coordinate_' + text, [2],
            (lambda v: lambda m, r: (set_coordinate(m, r, v), m)[1])(text))
    for text in ('1e308', '-1e308'):
        add('coordinate_' + text, [2, 4],
            (lambda v: lambda m, r: (set_coordinate(m, r, v), m)[1])(text))
    for text in ('abc', '1.2.3', '0x1p-3', '1e', '--1'):
        add('coordinate_text_' + re.sub(r'\W', '_', text), [2],
            (lambda v: lambda m, r: (set_coordinate(m, r, v), m)[1])(text), ascii_)
    add('coordinate_1000_digits', [0, 2],
        lambda m, r: (set_coordinate(m, r, '0.' + '0' * 998 + '1'), m)[1], ascii_)

    # --- physical names
    add('duplicate_physical_name', [2],
        lambda m, r: (replace_physical_name(m, 'face_c', 'face_a'), m)[1])
    add('duplicate_volume_name', [2],
        lambda m, r: (m.set_section_text('PhysicalNames', m.section_text('PhysicalNames')
                      .replace('$EndPhysicalNames', '3 9 "block"\n$EndPhysicalNames')
                      .replace('\n4\n', '\n5\n', 1)), m)[1])
    add('interface_name_missing', [2],
        lambda m, r: (replace_physical_name(m, 'face_b', 'face_x'), m)[1])
    add('volume_name_missing', [2],
        lambda m, r: (replace_physical_name(m, 'block', 'blocks'), m)[1])
    add('physical_name_unterminated', [2],
        lambda m, r: (m.set_section_text('PhysicalNames', m.section_text('PhysicalNames')
                      .replace('"face_b"', '"face_b')), m)[1])
    add('physical_names_count_plus_1', [2],
        lambda m, r: (m.set_section_text('PhysicalNames', m.section_text('PhysicalNames')
                      .replace('\n4\n', '\n5\n', 1)), m)[1])
    add('physical_name_10000_chars', [0, 2],
        lambda m, r: (replace_physical_name(m, 'face_c', 'c' * 10000), m)[1])

    # --- sections
    def drop(name):
        return lambda m, r: (m.sections.pop(m.section_index(name)), m)[1]
    for name in ('MeshFormat', 'PhysicalNames', 'Nodes', 'Elements'):
        add('missing_section_' + name, [2], drop(name))
    add('missing_section_Entities', [2], drop('Entities'), v41)

    def duplicate_section(name):
        def f(m, r):
            k = m.section_index(name)
            m.sections.insert(k + 1, list(m.sections[k]))
            return m
        return f
    add('duplicate_section_Nodes', [2], duplicate_section('Nodes'))
    add('duplicate_section_Elements', [2], duplicate_section('Elements'))
    add('duplicate_section_PhysicalNames', [2], duplicate_section('PhysicalNames'))

    def swap_sections(a, b):
        def f(m, r):
            i, j = m.section_index(a), m.section_index(b)
            m.sections[i], m.sections[j] = m.sections[j], m.sections[i]
            return m
        return f
    add('reordered_Elements_before_Nodes', [0, 2], swap_sections('Nodes', 'Elements'))
    add('reordered_PhysicalNames_last', [0, 2],
        lambda m, r: (m.sections.append(m.sections.pop(m.section_index('PhysicalNames'))), m)[1])

    def edit_bytes(func):
        return lambda m, r: func(m.serialize())
    add('missing_EndNodes', [2], edit_bytes(lambda d: d.replace(b'\n$EndNodes\n', b'\n', 1)))
    add('missing_EndElements', [2], edit_bytes(lambda d: d.replace(b'\n$EndElements\n', b'\n')))
    add('misspelled_Nodes', [2], edit_bytes(lambda d: d.replace(b'$Nodes\n', b'$Nodse\n', 1)))
    add('trailing_garbage_text', [0, 2], edit_bytes(lambda d: d + b'garbage after the end\n'))
    add('trailing_binary_garbage', [0, 2],
        edit_bytes(lambda d: d + bytes(random.Random(7).randrange(256) for _ in range(300))))

    # --- $MeshFormat
    version = b'2.2' if fmt == 'msh22' else b'4.1'
    for bad in (b'4.0', b'3.0', b'5.0', b'2.1', b'abc', b'4'):
        if bad != version:
            add('version_' + bad.decode().replace('.', '_'), [2],
                (lambda v: edit_bytes(lambda d: d.replace(b'\n' + version + b' ',
                                                           b'\n' + v + b' ', 1)))(bad))
    flag = b' 1 8\n' if binary else b' 0 8\n'
    add('file_type_flag_flipped', [2],
        edit_bytes(lambda d: d.replace(flag, b' 0 8\n' if binary else b' 1 8\n', 1)))
    add('data_size_4', [2], edit_bytes(lambda d: d.replace(flag, flag[:3] + b'4\n', 1)))
    add('endianness_int_wrong', [2],
        edit_bytes(lambda d: d.replace(b'\x01\x00\x00\x00\n', b'\x00\x00\x00\x01\n', 1)), binary)

    # --- whole file
    add('empty_file', [2], lambda m, r: b'')
    add('only_newlines', [2], lambda m, r: b'\n\n\n')
    add('binary_garbage_file', [2],
        lambda m, r: bytes(r.randrange(256) for _ in range(4096)))
    add('text_garbage_file', [2],
        lambda m, r: ''.join(r.choice('abc $\n0123.') for _ in range(4096)).encode())
    return out


def random_mutation(data, rng, binary):
    """(name, bytes) of one random mutation of the file `data`."""
    kind = rng.choice(['truncate', 'truncate', 'bitflip', 'bitflip', 'overwrite'] +
                      ([] if binary else ['delete_line', 'duplicate_line', 'swap_lines']))
    if kind == 'truncate':
        cut = rng.randrange(len(data))
        return 'truncate_at_%d' % cut, data[:cut]
    b = bytearray(data)
    if kind == 'bitflip':
        flips = rng.choice([1, 1, 2, 4, 8])
        for _ in range(flips):
            k = rng.randrange(len(b))
            b[k] ^= 1 << rng.randrange(8)
        return 'bitflip_%d_bits' % flips, bytes(b)
    if kind == 'overwrite':
        k = rng.randrange(len(b))
        n = rng.choice([1, 4, 16])
        b[k:k + n] = bytes(rng.randrange(256) for _ in range(n))
        return 'overwrite_%d_bytes_at_%d' % (n, k), bytes(b)
    lines = data.split(b'\n')
    i = rng.randrange(len(lines))
    if kind == 'delete_line':
        del lines[i]
    elif kind == 'duplicate_line':
        lines.insert(i, lines[i])
    else:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    return '%s_%d' % (kind, i + 1), b'\n'.join(lines)


def generate_meshes(fmt, base_dir, out_dir, count):
    tag = {'msh41': 'm41', 'msh41_binary': 'm41b', 'msh22': 'm22'}[fmt]
    bases = {}
    for order in BASE_ORDERS:
        path = os.path.join(base_dir, 'fuzz_block_%s_%s.msh' % (order, fmt))
        with open(path, 'rb') as f:
            data = f.read()
        if MeshFile.parse(data).serialize() != data:
            sys.exit('generate.py: %s does not read back byte for byte' % path)
        bases[order] = data
    plan = []
    for order in BASE_ORDERS:
        for name, expected, func in mesh_mutations(fmt, order):
            plan.append((order, name, expected, func))
    if len(plan) > count:
        sys.exit('generate.py: %d deterministic %s mutations, more than %d' % (len(plan), fmt, count))
    while len(plan) < count:
        plan.append((BASE_ORDERS[len(plan) % 2], None, RANDOM, None))
    entries = []
    for index, (order, name, expected, func) in enumerate(plan):
        rng = random.Random('%s:%d' % (fmt, index))
        if func is None:
            name, data = random_mutation(bases[order], rng, fmt == 'msh41_binary')
        else:
            result = func(MeshFile.parse(bases[order]), rng)
            data = result if isinstance(result, bytes) else result.serialize()
        slug = re.sub(r'[^A-Za-z0-9_]', '_', name)[:60]
        mesh = '%s_%03d_%s_%s.msh' % (tag, index, order, slug)
        case = 'case_%s_%03d.nml' % (tag, index)
        with open(os.path.join(out_dir, mesh), 'wb') as f:
            f.write(data)
        with open(os.path.join(out_dir, case), 'w') as f:
            f.write(MESH_CASE.format(mesh=mesh))
        entries.append(dict(id='%s_%03d' % (tag, index), case=case, target=mesh,
                            mutation='%s/%s' % (order, name), expected=expected, names=[mesh],
                            mesh_dir=False))
    return entries


# ====================================================================== namelists
#: key -> type of every namelist key (src/input/nml_*.f90); 'r' real, 'i' integer, 'l' logical,
#: 's' string
KEY_TYPES = {}
for _group, _keys in {
        'run': 's:title s:output s:mode_shapes_msh s:log_level',
        'body': 's:name s:mesh_file s:volumes r:young r:poisson r:density s:type i:num_modes '
                'r:modal_damping r:mass r:center_of_mass r:inertia r:position r:orientation '
                'r:velocity r:angular_velocity '
                'l:geometric_stiffness s:coarse_meshes s:modes_file',
        'interface': 's:body s:name s:mpc s:weighting s:virtual_node r:position s:rc',
        'modes': 'i:num_modes r:shift_hz s:formulation s:rc_label r:tolerance '
                 'i:lanczos_vectors s:basis l:out_of_core s:ooc_tmpdir i:memory_limit_mb '
                 'r:compression_tolerance s:eigensolver r:max_frequency_hz l:sturm_check',
        'model': 's:selection r:speed_tolerance r:force_tolerance i:candidate_modes '
                 'r:resonance_floor',
        'mechanism': 's:crank r:crank_angle_deg r:crank_speed r:gravity s:label '
                     'r:progress_interval i:animation_frames',
        'marker': 's:body s:name r:position',
        'joint': 's:name s:type s:body1 s:marker1 s:body2 s:marker2 r:axis',
        'load': 's:name s:type s:body s:marker r:direction r:value r:stall_torque '
                'r:free_speed r:switch_off r:coefficient s:law r:initial r:final r:speed '
                'r:t_start r:duration r:table_time r:table_value s:interpolation s:beyond',
        'driver': 's:name s:joint s:quantity r:offset s:law r:initial r:final r:speed '
                  'r:t_start r:duration r:table_time r:table_value s:interpolation s:beyond',
        'spring': 's:name s:body1 s:marker1 s:body2 s:marker2 r:stiffness r:damping '
                  'r:free_length',
        'torsion_spring': 's:name s:joint r:stiffness r:damping r:free_angle',
        'bushing': 's:name s:body1 s:marker1 s:body2 s:marker2 r:stiffness r:damping',
        'pressure': 'r:bore r:stroke r:conrod_length r:compression_ratio r:intake_pressure '
                    'r:exhaust_pressure r:polytropic_exponent r:wiebe_a r:wiebe_m '
                    'r:combustion_start_deg r:combustion_duration_deg r:heat_per_cycle '
                    'r:target_peak_pressure r:reference_pressure s:table_file',
        'integrator': 'r:h r:t_end r:rho_inf r:newton_atol r:newton_rtol i:max_iterations '
                      'r:min_step r:rank_rtol s:jacobian i:tangent_reuse'}.items():
    for _item in _keys.split():
        _type, _key = _item.split(':')
        KEY_TYPES[(_group, _key)] = _type
#: (group, key, value) that issue 10 lists as slipping through; every case gets those of its groups
ISSUE_VALUES = [('integrator', 'h', 'Inf'), ('integrator', 'h', '1e300'),
                ('integrator', 't_end', 'Inf'), ('mechanism', 'gravity', 'NaN, 0, 0'),
                ('mechanism', 'crank_angle_deg', '1e300'), ('load', 'stall_torque', 'NaN'),
                ('body', 'young', 'Inf'), ('body', 'density', 'Inf'),
                ('interface', 'position', '0, NaN, 0')]
#: the &modes keys of issue 12 (out-of-core, memory cap, compression; nml_modes.f90), each value
#: put into (or added to) &modes of every case, a &modes group added where the case has none:
#: (key, value, expected). Wrong types, out of range (memory_limit_mb >= -1 and <= 1e9,
#: compression_tolerance in [0, 1) and refused above 0), too long (ooc_tmpdir <= 256 characters);
#: with out_of_core = .true. (the fourth item, added to the group) an ooc_tmpdir that is no folder
#: (3, a file error, before MUMPS would fail in the factorisation); eigensolver not one of 'auto',
#: 'arpack', 'block'.
MODES_MEMORY_VALUES = [
    ('out_of_core', '.maybe.', [2]), ('out_of_core', "'yes'", [2]), ('out_of_core', '1.5', [2]),
    ('ooc_tmpdir', "'%s'" % ('d' * 300), [2]), ('ooc_tmpdir', '.true.', [2]),
    ('memory_limit_mb', '-2', [2]), ('memory_limit_mb', '1.5', [2]),
    ('memory_limit_mb', "'lots'", [2]), ('memory_limit_mb', '99999999999999999999', [2]),
    ('memory_limit_mb', '2000000000', [2]),
    ('compression_tolerance', '1.0', [2]), ('compression_tolerance', '-0.1', [2]),
    ('compression_tolerance', 'NaN', [2]), ('compression_tolerance', '1e999', [2]),
    ('compression_tolerance', "'steel'", [2]), ('compression_tolerance', '0.5', [2]),
    ('ooc_tmpdir', "'no-such-folder'", [3], 'out_of_core = .true.'),
    ('ooc_tmpdir', "'/dev/zero'", [3], 'out_of_core = .true.'),
    ('eigensolver', "'lobpcg'", [2]), ('eigensolver', '3', [2]), ('eigensolver', '.true.', [2]),
    ('eigensolver', "'%s'" % ('b' * 300), [2])]
#: file name of the not-HDF5 file that &body modes_file mutations name (written by
#: generate_namelists next to the cases, passed by absolute path)
NOT_HDF5_MODES = 'n_not_hdf5_modes.h5'
#: mutations that do not depend on the case they start from
WHOLE_FILE = ('empty_file', 'binary_garbage_file')
SINGLE_GROUPS = ('run', 'modes', 'model', 'mechanism', 'pressure', 'integrator')
#: keys whose +1e308 is out of a documented or stated range (issue 10 names crank_angle_deg,
#: t_end; poisson lies in (-1, 0.5), rho_inf in [0, 1])
BOUNDED_ABOVE = {'poisson', 'rho_inf', 'crank_angle_deg', 't_end', 'compression_tolerance'}
#: keys that must be positive, so -1e308 is out of range
POSITIVE = {'young', 'density', 'mass', 'h', 't_end', 'bore', 'stroke', 'conrod_length',
            'compression_ratio', 'intake_pressure', 'target_peak_pressure', 'tolerance',
            'speed_tolerance', 'force_tolerance', 'inertia'}


class Group:
    def __init__(self, name, start, end):
        self.name, self.start, self.end = name, start, end   # text[start] == '&', text[end] == '/'
        self.keys = []             # [key, key_start, value_start, value_end]


def parse_groups(text):
    """The namelist groups of `text`, with the span of every key and value (quotes, '!' comments
    and '/' inside strings respected)."""
    groups = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == '!':
            i = text.find('\n', i)
            i = n if i < 0 else i
            continue
        if c != '&':
            i += 1
            continue
        m = re.match(r'&(\w+)', text[i:])
        group = Group(m.group(1).lower(), i, -1)
        j = i + len(m.group(0))
        while j < n:
            c = text[j]
            if c in '\'"':
                k = j + 1
                while k < n:
                    if text[k] == c:
                        if k + 1 < n and text[k + 1] == c:
                            k += 2
                            continue
                        break
                    k += 1
                j = k + 1
            elif c == '!':
                j = text.find('\n', j)
                j = n if j < 0 else j
            elif c == '/':
                group.end = j
                break
            else:
                km = re.match(r'([A-Za-z_]\w*)\s*=', text[j:])
                if km and (j == 0 or not (text[j - 1].isalnum() or text[j - 1] == '_')):
                    if group.keys:
                        group.keys[-1][3] = j
                    group.keys.append([km.group(1).lower(), j, j + len(km.group(0)), -1])
                    j += len(km.group(0))
                else:
                    j += 1
        if group.keys:
            group.keys[-1][3] = group.end
        for key in group.keys:          # value_end: strip the separating comma and blanks
            value = text[key[2]:key[3]]
            value = re.sub(r'(![^\n]*\n|\s|,)*$', '', value)
            key[3] = key[2] + len(value)
        groups.append(group)
        i = j + 1
    return groups


def splice(text, start, end, new):
    return text[:start] + new + text[end:]


def namelist_mutations(text, base, not_hdf5=NOT_HDF5_MODES):
    """(name, expected, names-extra, text or bytes) of the deterministic mutations of one case.
    not_hdf5: path of a file that is not HDF5 (for &body modes_file)."""
    groups = parse_groups(text)
    out = []
    keyed = [(g, k) for g in groups for k in g.keys]

    def typed(kind):
        return [(g, k) for g, k in keyed if KEY_TYPES.get((g.name, k[0])) == kind]

    def first(items):
        return items[:1]

    # positive controls
    out.append(('unchanged', [0], [], text))
    out.append(('comment_after_slash', [0], [],
                splice(text, groups[0].end, groups[0].end + 1, '/ ! a comment after the group')))
    reordered = ''.join(text[g.start:g.end + 1] + '\n' for g in reversed(groups))
    out.append(('groups_reversed', [0], [], reordered))

    # wrong types and non-finite / huge values: the first and last real key, every integer
    reals = typed('r')
    picks = reals[:1] + reals[-1:] if len(reals) > 1 else reals
    for g, k in picks:
        tag = '%s_%s' % (g.name, k[0])
        who = ['&' + g.name, k[0]]
        out.append(('real_is_string_' + tag, [2], who, splice(text, k[2], k[3], "'steel'")))
        out.append(('real_is_logical_' + tag, [2], who, splice(text, k[2], k[3], '.maybe.')))
        for bad in ('nan', 'NaN', 'inf', '-Infinity', '1e999', '-1e999'):
            out.append(('real_%s_%s' % (bad.replace('-', 'minus_'), tag), [2], who,
                        splice(text, k[2], k[3], bad)))
        out.append(('real_1e308_' + tag, [2] if k[0] in BOUNDED_ABOVE else [0, 2, 4], who,
                    splice(text, k[2], k[3], '1e308')))
        out.append(('real_minus_1e308_' + tag, [2] if k[0] in POSITIVE else [0, 2, 4], who,
                    splice(text, k[2], k[3], '-1e308')))
    for g, k in typed('r'):
        if k[0] in BOUNDED_ABOVE and (g, k) not in picks:
            out.append(('real_1e308_%s_%s' % (g.name, k[0]), [2], ['&' + g.name, k[0]],
                        splice(text, k[2], k[3], '1e308')))
            out.append(('real_nan_%s_%s' % (g.name, k[0]), [2], ['&' + g.name, k[0]],
                        splice(text, k[2], k[3], 'nan')))
    for g, k in first(typed('i')):
        tag = '%s_%s' % (g.name, k[0])
        who = ['&' + g.name, k[0]]
        out.append(('integer_is_1.5_' + tag, [2], who, splice(text, k[2], k[3], '1.5')))
        out.append(('integer_is_string_' + tag, [2], who, splice(text, k[2], k[3], "'many'")))
        out.append(('integer_overflow_' + tag, [2], who,
                    splice(text, k[2], k[3], '99999999999999999999')))
        out.append(('integer_negative_' + tag, [2], who, splice(text, k[2], k[3], '-3')))
    for g, k in first(typed('s')):
        out.append(('unterminated_string_%s_%s' % (g.name, k[0]), [2], ['&' + g.name],
                    splice(text, k[2], k[3], " 'no closing quote")))
    bodies = [g for g in groups if g.name == 'body']
    flexible = [g for g in bodies if 'young' in [k[0] for k in g.keys]]
    if flexible:
        g = flexible[0]
        out.append(('logical_is_maybe_body_geometric_stiffness', [2],
                    ['&body', 'geometric_stiffness'],
                    splice(text, g.end, g.end, ', geometric_stiffness = .maybe. ')))

    # keys
    g = max(groups, key=lambda grp: len(grp.keys))
    k = g.keys[0]
    out.append(('repeated_key_%s_%s' % (g.name, k[0]), [2], ['&' + g.name, k[0]],
                splice(text, g.end, g.end, ', %s = %s ' % (text[k[1]:k[2]].rstrip(' ='),
                                                          text[k[2]:k[3]]))))
    out.append(('unknown_key_%s' % g.name, [2], ['&' + g.name, 'num_modez'],
                splice(text, g.end, g.end, ', num_modez = 4 ')))
    out.append(('unknown_group', [2], ['&modez'], text + '&modez num_modes = 4 /\n'))

    # groups: repeated, missing, unclosed, text after '/'
    for g in groups:
        if g.name in SINGLE_GROUPS:
            out.append(('repeated_group_' + g.name, [2], ['&' + g.name],
                        text + text[g.start:g.end + 1] + '\n'))
            break
    else:
        out.append(('repeated_group_modes', [2], ['&modes'],
                    text + '&modes num_modes = 4 /\n&modes num_modes = 6 /\n'))
    no_body = text
    for g in reversed(bodies):
        no_body = splice(no_body, g.start, g.end + 1, '')
    out.append(('missing_group_body', [2], ['&body'], no_body))
    dup = bodies[0]
    out.append(('repeated_body_name', [2], ['&body'],
                splice(text, dup.end + 1, dup.end + 1, '\n' + text[dup.start:dup.end + 1])))
    for name in ('joint', 'mechanism', 'interface'):
        gs = [g for g in groups if g.name == name]
        if gs:
            t = text
            for g in reversed(gs):
                t = splice(t, g.start, g.end + 1, '')
            out.append(('missing_groups_' + name, [0, 2, 4], [], t))
            break
    for g in (groups[0], groups[len(groups) // 2], groups[-1]):
        out.append(('unclosed_group_%s_%d' % (g.name, groups.index(g)), [2], ['&' + g.name],
                    splice(text, g.end, g.end + 1, '')))
    g = groups[len(groups) // 2]
    out.append(('text_after_slash_' + g.name, [2], [],
                splice(text, g.end, g.end + 1, '/ num_modes = 4')))
    out.append(('second_group_on_closing_line_' + g.name, [2], [],
                splice(text, g.end, g.end + 1, '/ &modez /')))

    # dofs, paths, sizes
    for g in groups:
        for k in g.keys:
            if g.name == 'interface' and k[0] == 'rc':
                out.append(('repeated_dof_rc', [2], ['rc'], splice(text, k[2], k[3], "'Tx Tx'")))
                break
        else:
            continue
        break
    for g in bodies:
        for k in g.keys:
            if k[0] == 'mesh_file':
                name = text[k[2]:k[3]].strip().strip('\'"')
                fill = 256 - len(name)          # the first 256 characters name `name`
                long = './' * (fill // 2) + '/' * (fill % 2) + name + '.missing'
                out.append(('mesh_path_cut_at_256', [2, 3], ['mesh_file'],
                            splice(text, k[2], k[3], "'%s'" % long)))
                out.append(('mesh_file_dev_zero', [3], ['zero'],
                            splice(text, k[2], k[3], "'/dev/zero'")))
                out.append(('mesh_file_is_folder', [3], ['..'],
                            splice(text, k[2], k[3], "'..'")))
                break
        else:
            continue
        break
    run = [g for g in groups if g.name == 'run']
    if run:
        g = run[0]
        out.append(('output_outside_dot_dot', [2], ['output'],
                    splice(text, g.end, g.end, ", output = '../escaped' ")))
        out.append(('output_absolute', [2], ['output'],
                    splice(text, g.end, g.end, ", output = '/nonexistent-ffrf-dir/out' ")))
        out.append(('title_5000_chars', [0, 2], [],
                    splice(text, g.end, g.end, ", title = '%s' " % ('t' * 5000))))
    out.append(('comment_line_600_chars', [0, 2], [],
                '! ' + 'c' * 600 + '\n' + text))
    out.append(('line_1000_chars_of_blanks', [0, 2], [],
                splice(text, groups[0].end, groups[0].end, ' ' * 1000)))
    mech = [g for g in groups if g.name == 'mechanism']
    if mech:
        g = mech[0]
        out.append(('animation_frames_1e9', [2], ['animation_frames'],
                    splice(text, g.end, g.end, ', animation_frames = 1000000000 ')))
    integ = [g for g in groups if g.name == 'integrator']
    if integ:
        g = integ[0]
        out.append(('h_negative', [2], ['h'], splice(text, g.end, g.end, ', h = -1.0 ')))
    # the pressure table is read only for a pressure load (a case without one never opens it)
    if integ and re.search(r"type\s*=\s*'pressure'", text):
        g = integ[0]
        out.append(('table_dev_zero', [3], ['zero'],
                    text + "&pressure table_file = '/dev/zero' /\n" if 'pressure' not in
                    [x.name for x in groups] else text.replace('&pressure ',
                                                               "&pressure table_file = "
                                                               "'/dev/zero', ", 1)))
    # values issue 10 names: each replaces the key's value, or is added to the group
    for group, key, value in ISSUE_VALUES:
        gs = [g for g in groups if g.name == group and
              (group != 'load' or 'stall_torque' in [k[0] for k in g.keys])]
        if not gs:
            continue
        g = gs[0]
        keys = [k for k in g.keys if k[0] == key]
        new = (splice(text, keys[0][2], keys[0][3], ' ' + value) if keys else
               splice(text, g.end, g.end, ', %s = %s ' % (key, value)))
        out.append(('issue_%s_%s_%s' % (group, key, re.sub(r'\W', '_', value)), [2],
                    ['&' + group, key], new))

    out += issue12_mutations(text, groups, not_hdf5)
    out += issue23_mutations(text, groups)

    # whole file
    out.append(('empty_file', [2], [], ''))
    out.append(('binary_garbage_file', [2], [],
                bytes(random.Random(base).randrange(256) for _ in range(2048))))
    out.append(('nul_bytes_in_group', [2], [],
                splice(text, groups[0].end, groups[0].end, ', \0\0\0 ')))
    return out


def is_mechanism(groups):
    """A case with &joint groups is a mechanism run (docs/input.md "Command line"); a &mechanism
    group alone says so too."""
    return any(g.name in ('joint', 'mechanism') for g in groups)


def issue12_mutations(text, groups, not_hdf5):
    """Mutations of the keys issue 12 added (names start 'issue12_', every case gets them):
    &modes out_of_core, ooc_tmpdir, memory_limit_mb, compression_tolerance (MODES_MEMORY_VALUES)
    and &body modes_file: in a mechanism case on the first flexible body a missing file, /dev/zero,
    a folder (exit 3, naming the path), a file that is not HDF5 (3), a 300-character path and a
    number (2), and on a rigid body (2); in a modal case any modes_file (2: modal runs compute
    their modes). Stored modes of another model are refused by the run's check
    (regression_mode_reuse_errors, regression_mode_reuse_check), which needs a results file."""
    out = []
    modes = [g for g in groups if g.name == 'modes']
    for key, value, expected, *more in MODES_MEMORY_VALUES:
        more = ', ' + more[0] if more else ''
        if not modes:
            new = text + '&modes %s = %s%s /\n' % (key, value, more)
        else:
            g = modes[0]
            keys = [k for k in g.keys if k[0] == key]
            new = (splice(text, keys[0][2], keys[0][3], value + more) if keys else
                   splice(text, g.end, g.end, ', %s = %s%s ' % (key, value, more)))
        out.append(('issue12_modes_%s_%s' % (key, re.sub(r'\W', '_', value)[:20]), expected,
                    ['&modes', key], new))
    bodies = [g for g in groups if g.name == 'body']

    def body_type(g):
        values = [text[k[2]:k[3]].strip().strip('\'"').lower() for k in g.keys if k[0] == 'type']
        return values[0] if values else ''
    rigid = [g for g in bodies if body_type(g) == 'rigid']
    flexible = [g for g in bodies if body_type(g) != 'rigid' and
                'mesh_file' in [k[0] for k in g.keys]]
    mechanism = is_mechanism(groups)

    def with_modes_file(g, value):
        return splice(text, g.end, g.end, ', modes_file = %s ' % value)
    if flexible and not mechanism:
        out.append(('issue12_modes_file_in_modal_run', [2], ['&body', 'modes_file'],
                    with_modes_file(flexible[0], "'modes.h5'")))
    if flexible and mechanism:
        g = flexible[0]
        for name, expected, value, names in (
                ('missing', [3], "'modes.h5.missing'", ['modes.h5.missing']),
                ('dev_zero', [3], "'/dev/zero'", ['zero']),
                ('folder', [3], "'..'", ['..']),
                ('not_hdf5', [3], "'%s'" % not_hdf5, [os.path.basename(not_hdf5)]),
                ('path_300_chars', [2], "'%s.h5'" % ('m' * 300), ['&body', 'modes_file']),
                ('is_number', [2], '42', ['&body', 'modes_file'])):
            out.append(('issue12_modes_file_' + name, expected, names, with_modes_file(g, value)))
    if rigid and mechanism:
        out.append(('issue12_modes_file_rigid_body', [2], ['&body', 'modes_file'],
                    with_modes_file(rigid[0], "'modes.h5'")))
    return out


def issue23_mutations(text, groups):
    """Outputs of a modal case that are one file (issue 23, item 2; names start 'issue23_',
    every modal case gets them): with one body, mode_shapes_msh naming the results file (also
    as './x.h5'), its temporary or its lock, the results file naming the mode shapes' option
    file; with two or more bodies, the results file naming a body's mode shapes file or its
    option file, the lock a body's mode shapes file. Exit 2 before any work (also by --check),
    naming mode_shapes_msh. Outputs stay inside --output-dir (refused otherwise), so an output
    naming an input is tested where inputs sit there (regression_faults_io_output_paths)."""
    if is_mechanism(groups):
        return []
    bodies = [g for g in groups if g.name == 'body']
    names = [text[k[2]:k[3]].strip().strip('\'"') for g in bodies[:1] for k in g.keys
             if k[0] == 'name']
    if len(bodies) == 1:
        variants = [('msh_is_results', 'x.h5', 'x.h5'), ('msh_is_results_dot', './x.h5', 'x.h5'),
                    ('msh_is_results_part', 'x.h5', 'x.h5.part'),
                    ('msh_is_results_lock', 'x.h5', 'x.h5.lock'),
                    ('results_is_msh_option', 'm.msh.opt', 'm.msh')]
    elif names:
        # two or more bodies: one mode shapes file each, <stem>_<body>.msh
        variants = [('results_is_body_msh', 'x_%s.msh' % names[0], 'x.msh'),
                    ('results_is_body_msh_option', 'x_%s.msh.opt' % names[0], 'x.msh'),
                    ('lock_is_body_msh', 'x_%s' % names[0], 'x.lock')]
    else:
        variants = []

    def with_run(output, msh):
        run = [g for g in groups if g.name == 'run']
        if not run:
            return text + "&run output = '%s', mode_shapes_msh = '%s' /\n" % (output, msh)
        g, new = run[0], text
        # replace the keys given, from the last one back (offsets stay valid), then add the rest
        given = sorted([k for k in g.keys if k[0] in ('output', 'mode_shapes_msh')],
                       key=lambda k: -k[2])
        for k in given:
            new = splice(new, k[2], k[3], " '%s'" % (output if k[0] == 'output' else msh))
        missing = [(key, value) for key, value in (('output', output), ('mode_shapes_msh', msh))
                   if key not in [k[0] for k in given]]
        insert = ''.join(", %s = '%s' " % kv for kv in missing)
        end = g.end + sum(len(" '%s'" % (output if k[0] == 'output' else msh)) - (k[3] - k[2])
                          for k in given)
        return splice(new, end, end, insert) if insert else new
    return [('issue23_' + name, [2], ['mode_shapes_msh'], with_run(output, msh))
            for name, output, msh in variants]


def generate_namelists(input_dir, out_dir, per_case_random):
    bases = sorted(f for f in os.listdir(input_dir) if f.endswith('.nml'))
    entries = []
    not_hdf5 = os.path.join(os.path.abspath(out_dir), NOT_HDF5_MODES)
    with open(not_hdf5, 'w') as f:
        f.write('this text file is not an HDF5 results file\n')
    case_index = 0
    for base in bases:
        with open(os.path.join(input_dir, base)) as f:
            text = f.read()
        if not re.search(r'^\s*&body\b', text, re.M):
            continue
        stem = base[:-4]
        # Half of the deterministic mutations per case (alternating between cases), the
        # unchanged copy in every case, the whole-file ones in the first two cases only.
        plan = [(n, e, x, t) for i, (n, e, x, t) in
                enumerate(namelist_mutations(text, base, not_hdf5))
                if n == 'unchanged' or n.startswith('issue_') or n.startswith('issue12_')
                or n.startswith('issue23_')
                or (n not in WHOLE_FILE and (i + case_index) % 2 == 0)
                or (n in WHOLE_FILE and case_index < 2)]
        case_index += 1
        for r in range(per_case_random):
            rng = random.Random('namelist:%s:%d' % (base, r))
            name, data = random_mutation(text.encode(), rng, False)
            plan.append((name, RANDOM, [], data))
        for index, (name, expected, extra, data) in enumerate(plan):
            slug = re.sub(r'[^A-Za-z0-9_]', '_', name)[:60]
            case = 'n_%s_%03d_%s.nml' % (stem, index, slug)
            with open(os.path.join(out_dir, case), 'wb') as f:
                f.write(data if isinstance(data, bytes) else data.encode('latin-1'))
            path_value = [x for x in extra if x.endswith('.missing') or x in ('zero', '..')
                          or x == NOT_HDF5_MODES]
            names, key_names = (path_value, []) if path_value else ([case], extra)
            entries.append(dict(id='n_%s_%03d' % (stem, index), case=case, target=case,
                                mutation='%s/%s' % (base, name), expected=expected, names=names,
                                key_names=key_names, mesh_dir=True))
    entries += special_files(input_dir, out_dir)
    return entries


def special_files(input_dir, out_dir):
    """Case and mesh files that are not regular files: a FIFO (opening it blocks for ever) and a
    folder as the case, a FIFO as the mesh. Exit 3, naming the file."""
    entries = []
    os.mkfifo(os.path.join(out_dir, 'n_special_case_fifo.nml'))
    os.mkdir(os.path.join(out_dir, 'n_special_case_folder.nml'))
    fifo_mesh = os.path.join(os.path.abspath(out_dir), 'n_special_mesh_fifo.msh')
    os.mkfifo(fifo_mesh)
    with open(os.path.join(input_dir, 'crank_rc1.nml')) as f:
        text = f.read().replace("'crank.msh'", "'%s'" % fifo_mesh)
    with open(os.path.join(out_dir, 'n_special_mesh_is_fifo.nml'), 'w') as f:
        f.write(text)
    for name, case, target in (('case_is_fifo', 'n_special_case_fifo.nml', None),
                               ('case_is_folder', 'n_special_case_folder.nml', None),
                               ('mesh_is_fifo', 'n_special_mesh_is_fifo.nml',
                                'n_special_mesh_fifo.msh')):
        target = target or case
        entries.append(dict(id='n_special_' + name, case=case, target=target,
                            mutation='special/' + name, expected=[3], names=[target],
                            mesh_dir=True))
    return entries


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--base-dir', help='folder of the base meshes fuzz_block_*.msh')
    parser.add_argument('--input-dir', help='folder of the case files *.nml')
    parser.add_argument('--out', required=True)
    parser.add_argument('--class', dest='classes', action='append',
                        choices=MESH_CLASSES + ('namelist',))
    parser.add_argument('--meshes-per-class', type=int, default=MESHES_PER_CLASS)
    parser.add_argument('--random-per-case', type=int, default=5)
    args = parser.parse_args()
    counts = {}
    for cls in args.classes or MESH_CLASSES + ('namelist',):
        out_dir = os.path.join(args.out, cls)
        os.makedirs(out_dir, exist_ok=True)
        for f in os.listdir(out_dir):
            path = os.path.join(out_dir, f)
            if os.path.isdir(path) and not os.path.islink(path):
                shutil.rmtree(path)
            else:
                os.remove(path)
        if cls == 'namelist':
            entries = generate_namelists(args.input_dir, out_dir, args.random_per_case)
        else:
            entries = generate_meshes(cls, args.base_dir, out_dir, args.meshes_per_class)
        with open(os.path.join(out_dir, 'manifest.json'), 'w') as f:
            json.dump(entries, f, indent=1)
        counts[cls] = len(entries)
    print('generate.py: ' + ', '.join('%s %d' % kv for kv in counts.items()))


if __name__ == '__main__':
    main()
