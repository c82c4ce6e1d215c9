"""Gmsh mesh files as editable objects for the negative-suite generator (standard library only).

MeshFile.parse(data) reads MSH 4.1 ASCII, MSH 4.1 binary (data size 8, little endian) and MSH 2.2
ASCII as gmsh 4.8.4 writes them, and serialize() writes them back byte for byte (the generator
asserts this on every base mesh before mutating it). Only $Nodes and $Elements are decoded; every
other section ($MeshFormat, $PhysicalNames, $Entities ...) is kept as raw text or bytes, editable as
a whole. Values are kept as read: ASCII coordinates stay strings (so a mutation can write 'nan' or
'1e999' literally), tags and counts are ints (or strings, in ASCII, to write non-numbers).

Layout (both formats of 4.1; gmsh manual, section "MSH file format"):
  $Nodes     numEntityBlocks numNodes minNodeTag maxNodeTag, then per block
             entityDim entityTag parametric numNodesInBlock, the tags, then the coordinates
  $Elements  numEntityBlocks numElements minElementTag maxElementTag, then per block
             entityDim entityTag elementType numElementsInBlock, then "tag node ..." per element
  MSH 2.2:   $Nodes count, "tag x y z" lines; $Elements count, "tag type ntags tags... nodes..."
"""
import struct

#: nodes per element of the Gmsh element types the generator writes or meets
NODES_PER_ELEMENT = {1: 2, 2: 3, 3: 4, 4: 4, 5: 8, 6: 6, 7: 5, 8: 3, 9: 6, 11: 10, 15: 1}
TET_TYPES = (4, 11)
TRI_TYPES = (2, 9)


class Block:
    """A node block (tags, coords) or an element block (elems: [tag, node, ...] lists)."""

    def __init__(self, header, tags=None, coords=None, elems=None):
        self.header = header          # 4.1: [dim, entity, parametric|type, count]; 2.2: None
        self.tags = tags
        self.coords = coords
        self.elems = elems


class MeshFile:
    def __init__(self):
        self.fmt = ''                 # 'msh41', 'msh41_binary' or 'msh22'
        self.sections = []            # [name, raw bytes of the whole section] or [name, None]
        self.node_header = []         # 4.1: [blocks, nodes, min, max]; 2.2: [nodes]
        self.node_blocks = []
        self.elem_header = []
        self.elem_blocks = []         # 2.2: one block, elems are whole lines [tag, type, ntags, ...]
        self.trailer = b''

    # ------------------------------------------------------------------ parsing
    @classmethod
    def parse(cls, data):
        self = cls()
        if data.startswith(b'$MeshFormat\n4.1 1 8\n'):
            self.fmt = 'msh41_binary'
        elif data.startswith(b'$MeshFormat\n4.1 0 8\n'):
            self.fmt = 'msh41'
        elif data.startswith(b'$MeshFormat\n2.2 0 8\n'):
            self.fmt = 'msh22'
        else:
            raise ValueError('not a gmsh 4.8.4 MSH 4.1 / 2.2 file')
        pos = 0
        while pos < len(data):
            end_name = data.index(b'\n', pos)
            name = data[pos + 1:end_name].decode()
            body = end_name + 1
            if self.fmt == 'msh41_binary' and name in ('Nodes', 'Elements'):
                stop = self._parse_binary(name, data, body)
                if data[stop:stop + len(name) + 6] != b'\n$End' + name.encode() + b'\n':
                    raise ValueError('binary section end not found')
                pos = stop + len(name) + 6
                self.sections.append([name, None])
                continue
            marker = b'$End' + name.encode() + b'\n'
            stop = data.index(marker, body)
            if name in ('Nodes', 'Elements'):
                lines = data[body:stop].decode().split('\n')[:-1]
                if self.fmt == 'msh41':
                    self._parse_ascii41(name, lines)
                else:
                    self._parse_ascii22(name, lines)
                self.sections.append([name, None])
            else:
                self.sections.append([name, data[pos:stop + len(marker)]])
            pos = stop + len(marker)
        return self

    def _parse_ascii41(self, name, lines):
        header = [int(v) for v in lines[0].split()]
        k = 1
        blocks = []
        for _ in range(header[0]):
            bh = [int(v) for v in lines[k].split()]
            k += 1
            n = bh[3]
            if name == 'Nodes':
                tags = [int(v) for v in lines[k:k + n]]
                coords = [lines[k + n + i].split() for i in range(n)]
                k += 2 * n
                blocks.append(Block(bh, tags=tags, coords=coords))
            else:
                elems = [[int(v) for v in lines[k + i].split()] for i in range(n)]
                k += n
                blocks.append(Block(bh, elems=elems))
        assert k == len(lines)
        if name == 'Nodes':
            self.node_header, self.node_blocks = header, blocks
        else:
            self.elem_header, self.elem_blocks = header, blocks

    def _parse_ascii22(self, name, lines):
        header = [int(lines[0])]
        if name == 'Nodes':
            rows = [line.split() for line in lines[1:]]
            block = Block(None, tags=[int(r[0]) for r in rows], coords=[r[1:] for r in rows])
            self.node_header, self.node_blocks = header, [block]
        else:
            block = Block(None, elems=[[int(v) for v in line.split()] for line in lines[1:]])
            self.elem_header, self.elem_blocks = header, [block]

    def _parse_binary(self, name, data, pos):
        def sizes(count):
            nonlocal pos
            values = list(struct.unpack_from('<%dQ' % count, data, pos))
            pos += 8 * count
            return values
        header = sizes(4)
        blocks = []
        for _ in range(header[0]):
            bh = list(struct.unpack_from('<3i', data, pos))
            pos += 12
            bh += sizes(1)
            n = bh[3]
            if name == 'Nodes':
                tags = sizes(n)
                flat = struct.unpack_from('<%dd' % (3 * n), data, pos)
                pos += 24 * n
                blocks.append(Block(bh, tags=tags,
                                    coords=[list(flat[3 * i:3 * i + 3]) for i in range(n)]))
            else:
                width = NODES_PER_ELEMENT[bh[2]] + 1
                flat = sizes(n * width)
                blocks.append(Block(bh, elems=[flat[width * i:width * (i + 1)] for i in range(n)]))
        if name == 'Nodes':
            self.node_header, self.node_blocks = header, blocks
        else:
            self.elem_header, self.elem_blocks = header, blocks
        return pos

    # ------------------------------------------------------------------ writing
    def serialize(self):
        out = []
        for name, raw in self.sections:
            if raw is not None:
                out.append(raw)
                continue
            if self.fmt == 'msh41_binary':
                out.append(b'$' + name.encode() + b'\n' + self._binary_body(name) +
                           b'\n$End' + name.encode() + b'\n')
            else:
                lines = self._ascii_lines(name)
                out.append(('$%s\n%s$End%s\n' % (name, ''.join(l + '\n' for l in lines),
                                                 name)).encode())
        return b''.join(out) + self.trailer

    def _ascii_lines(self, name):
        text = lambda values: ' '.join(str(v) for v in values)
        if name == 'Nodes':
            lines = [text(self.node_header)]
            for b in self.node_blocks:
                if self.fmt == 'msh41':
                    lines.append(text(b.header))
                    lines += [str(t) for t in b.tags]
                    lines += [text(c) for c in b.coords]
                else:
                    lines += [text([t] + c) for t, c in zip(b.tags, b.coords)]
            return lines
        lines = [text(self.elem_header)]
        for b in self.elem_blocks:
            if self.fmt == 'msh41':
                lines.append(text(b.header))
                lines += [text(e) + ' ' for e in b.elems]
            else:
                lines += [text(e) for e in b.elems]
        return lines

    def _binary_body(self, name):
        u64 = lambda values: struct.pack('<%dQ' % len(values), *[v % 2**64 for v in values])
        out = []
        if name == 'Nodes':
            out.append(u64(self.node_header))
            for b in self.node_blocks:
                out.append(struct.pack('<3i', *b.header[:3]) + u64(b.header[3:]))
                out.append(u64(b.tags))
                out.append(struct.pack('<%dd' % (3 * len(b.coords)),
                                       *[float(x) for c in b.coords for x in c]))
        else:
            out.append(u64(self.elem_header))
            for b in self.elem_blocks:
                out.append(struct.pack('<3i', *b.header[:3]) + u64(b.header[3:]))
                out.append(u64([v for e in b.elems for v in e]))
        return b''.join(out)

    # ------------------------------------------------------------------ views
    def elements(self):
        """(block, index, type, node tags) of every element."""
        for b in self.elem_blocks:
            for i, e in enumerate(b.elems):
                if self.fmt == 'msh22':
                    yield b, i, e[1], e[3 + e[2]:]
                else:
                    yield b, i, b.header[2], e[1:]

    def set_element_nodes(self, block, index, nodes):
        e = block.elems[index]
        if self.fmt == 'msh22':
            block.elems[index] = e[:3 + e[2]] + list(nodes)
        else:
            block.elems[index] = [e[0]] + list(nodes)

    def nodes(self):
        """(block, index, tag, coords) of every node."""
        for b in self.node_blocks:
            for i, t in enumerate(b.tags):
                yield b, i, t, b.coords[i]

    def coordinates(self):
        """tag -> (x, y, z) as floats."""
        return {t: tuple(float(x) for x in c) for _, _, t, c in self.nodes()}

    def max_node_tag(self):
        return max(t for _, _, t, _ in self.nodes())

    def max_element_tag(self):
        return max(b.elems[i][0] for b, i, _, _ in self.elements())

    def number(self, value):
        """A coordinate as this format stores it: a string in ASCII, a float in binary."""
        if self.fmt == 'msh41_binary':
            return float(value)
        return value if isinstance(value, str) else '%.16g' % value

    def add_nodes(self, coords, entity=(3, 1)):
        """Append nodes (new tags after the largest) and return their tags; headers updated."""
        first = self.max_node_tag() + 1
        tags = list(range(first, first + len(coords)))
        values = [[self.number(x) for x in c] for c in coords]
        if self.fmt == 'msh22':
            self.node_blocks[0].tags += tags
            self.node_blocks[0].coords += values
        else:
            self.node_blocks.append(Block([entity[0], entity[1], 0, len(tags)], tags=tags,
                                          coords=values))
        self.fix_headers()
        return tags

    def add_element(self, element_type, nodes, entity=(3, 1), physical=1):
        tag = self.max_element_tag() + 1
        if self.fmt == 'msh22':
            self.elem_blocks[0].elems.append([tag, element_type, 2, physical, entity[1]] +
                                             list(nodes))
        else:
            self.elem_blocks.append(Block([entity[0], entity[1], element_type, 1],
                                          elems=[[tag] + list(nodes)]))
        self.fix_headers()
        return tag

    def fix_headers(self):
        """Make the counts and tag ranges of $Nodes and $Elements agree with the data."""
        tags = [t for _, _, t, _ in self.nodes()]
        etags = [b.elems[i][0] for b, i, _, _ in self.elements()]
        if self.fmt == 'msh22':
            self.node_header = [len(tags)]
            self.elem_header = [len(etags)]
            return
        for b in self.node_blocks:
            b.header[3] = len(b.tags)
        for b in self.elem_blocks:
            b.header[3] = len(b.elems)
        self.node_header = [len(self.node_blocks), len(tags), min(tags), max(tags)]
        self.elem_header = [len(self.elem_blocks), len(etags), min(etags), max(etags)]

    def section_index(self, name):
        for k, (n, _) in enumerate(self.sections):
            if n == name:
                return k
        return -1

    def section_text(self, name):
        return self.sections[self.section_index(name)][1].decode('latin-1')

    def set_section_text(self, name, text):
        self.sections[self.section_index(name)][1] = text.encode('latin-1')
