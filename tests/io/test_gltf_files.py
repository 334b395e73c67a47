#!/usr/bin/env python3
"""`harmonia atlas IN OUT.glb|OUT.gltf` on glTF files, judged by tools that share no code with the
library: every file of ../shared/data/gltf, and files written here (a small JSON + struct writer of
our own) that each hold features the writer must carry through: a skin with its animation (8- and
16-bit joints, float and normalized-byte weights), morph targets (POSITION, NORMAL, TANGENT deltas)
animated by weights, sparse accessors (with and without a buffer view), normalized 8- and 16-bit
texture coordinates under 8- and 16-bit indices, 16-bit indices that the seams push past 65535
vertices, a mesh placed twice (once mirrored) in a default scene that is not the first, an empty
scene, no scene at all, interleaved attributes with COLOR_0 in normalized bytes and a custom
`_FOO`, strips and fans (indexed or not, with stitching) beside lines and points, primitives
sharing vertex accessors and an index buffer view, GPU instancing, lights, a camera, material
variants, KHR_mesh_quantization, an external .bin, a data URI, two buffers, an external image;
and the program's own output fed back to it.

For each run (input, output, options):
  * attributes: every attribute and morph-target delta of the input reaches every corner of every
    triangle of the output unchanged (decoded by ../shared/tools/gltfread.py, compared exactly,
    component types kept; triangles in order, strips and fans up to a rotation of their corners,
    their stitching triangles dropped); the atlas is in the expected TEXCOORD_n, `_CHART` holds one
    chart per triangle, a vertex is split only where (uv, chart) differ; the indices are of the
    input's type unless the new vertex count needs a wider one; primitives not rewritten (lines,
    points, meshes --mesh leaves out) are as they were;
  * document: everything but the rewritten primitives' accessors is the input's (materials, nodes,
    skins and animations with their accessors decoded, images' bytes or the files their URIs
    reach, extras, extensions), no accessor or buffer view is left over, all the binary data is in
    one buffer (OUT.bin beside OUT.gltf, named by a percent-encoded URI);
  * validator: the Khronos glTF validator (npm gltf-validator) finds no error in the output and no
    warning the input did not have;
  * atlas: each atlas (per mesh, primitive or scene, as --group says) written as an OBJ of the
    output's positions (in the world frame of the mesh's first instance) and UVs (v flipped back)
    and judged by ../shared/tools/atlaseval.py: valid (no flips, overlapping texels, boundary
    crossings or faces left out), no mirrored chart, inside the unit square; its charts and faces
    are those the program's --json report gives.
And refusals: a --texcoord that would overwrite a set, one that leaves a gap, and a file whose
accessor overruns its buffer view exit non-zero, name the place, and write nothing; writing
OUT.gltf never overwrites a file the input reads.

Compressed input (EXT_meshopt_compression) cannot be decoded here: its output is checked by the
validator, the atlas, gltfread's decoding and `harmonia info`'s triangle counts.

    /usr/bin/python3 tests/io/test_gltf_files.py -v      (or pytest; -k PATTERN picks tests)

Environment: HARMONIA_CLI (the program; default build/harmonia), HARMONIA_SHARED_DATA (default
../shared/data beside the checkout; the tools are in its ../tools), HARMONIA_NODE_PATH (the
node_modules folder holding gltf-validator; default ~/.cache/harmonia-test-tools/node_modules,
where .ci/install-deps puts it), HARMONIA_KEEP_TEST_FILES=1 keeps the scratch folder. Without the
corpus, the tools or the validator the tests that need them are skipped (exit 77 when all are),
except under CI=true, where they fail. Standard library only; about a minute on 2 cores.
"""

import atexit
import base64
import hashlib
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest
import urllib.parse
import warnings
import zlib

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.environ.get('HARMONIA_CLI') or os.path.join(SOURCE, 'build', 'harmonia')
SHARED_DATA = os.environ.get('HARMONIA_SHARED_DATA') or os.path.join(os.path.dirname(SOURCE), 'shared', 'data')
TOOLS = os.path.join(os.path.dirname(os.path.abspath(SHARED_DATA)), 'tools')
CORPUS = os.path.join(SHARED_DATA, 'gltf')
NODE_PATH = os.environ.get('HARMONIA_NODE_PATH') or os.path.join(
    os.path.expanduser('~'), '.cache', 'harmonia-test-tools', 'node_modules')
UNDER_CI = os.environ.get('CI') == 'true'

if os.path.isfile(os.path.join(TOOLS, 'gltfread.py')):
    sys.dont_write_bytecode = True  # nothing written into the shared tools' folder
    sys.path.insert(0, TOOLS)
    import atlaseval  # noqa: E402
    import gltfread  # noqa: E402
else:
    atlaseval = gltfread = None

FLOAT, U8, U16, U32, I8, I16 = 5126, 5121, 5123, 5125, 5120, 5122
INDEX_LIMIT = {U8: 255, U16: 65535, U32: 4294967295}  # vertex counts each index type can address
INDEX_WIDER = {U8: U16, U16: U32}
NCOMP = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3, 'VEC4': 4, 'MAT2': 4, 'MAT3': 9, 'MAT4': 16}
FMT = {FLOAT: 'f', U8: 'B', U16: 'H', U32: 'I', I8: 'b', I16: 'h'}


def missing(what):
    """Skips the calling test for want of `what`; fails it under CI=true."""
    if UNDER_CI:
        raise AssertionError('%s (CI=true needs it: .ci/install-deps and ../shared beside the checkout)' % what)
    raise unittest.SkipTest(what)


def need_tools():
    if gltfread is None:
        missing('no gltfread.py / atlaseval.py in %s' % TOOLS)
    if not os.path.isfile(CLI):
        missing('no harmonia program at %s (HARMONIA_CLI)' % CLI)


# ------------------------------------------------------------------------------ a glTF writer

def png_bytes(width, height, rgb):
    raw = b''.join(b'\x00' + bytes(rgb) * width for _ in range(height))

    def chunk(kind, data):
        return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, 2, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))


def f32(x):
    return struct.unpack('<f', struct.pack('<f', x))[0]


class Doc:
    """A glTF document under construction: JSON plus one binary buffer."""

    def __init__(self):
        self.j = {'asset': {'version': '2.0', 'generator': 'harmonia tests/io/test_gltf_files.py',
                            'extras': {'note': 'written by the test'}}}
        self.bin = bytearray()

    def add(self, key, obj):
        items = self.j.setdefault(key, [])
        items.append(obj)
        return len(items) - 1

    def view(self, data, target=None, stride=None):
        while len(self.bin) % 4:
            self.bin += b'\0'
        view = {'buffer': 0, 'byteOffset': len(self.bin), 'byteLength': len(data)}
        if stride:
            view['byteStride'] = stride
        if target:
            view['target'] = target
        self.bin += data
        return self.add('bufferViews', view)

    @staticmethod
    def pack(values, ctype, kind, stride=None):
        n = NCOMP[kind]
        fmt = '<' + FMT[ctype] * n
        size = struct.calcsize(fmt)
        out = bytearray()
        for value in values:
            value = value if isinstance(value, (tuple, list)) else (value,)
            assert len(value) == n, (value, kind)
            out += struct.pack(fmt, *value)
            if stride:
                out += b'\0' * (stride - size)
        return bytes(out)

    def accessor(self, values, ctype, kind, normalized=False, target=None, minmax=False, vertex=True, **extra):
        """A tightly packed accessor in a view of its own; vertex attributes padded to 4 bytes."""
        size = struct.calcsize('<' + FMT[ctype] * NCOMP[kind])
        stride = (size + 3) // 4 * 4 if vertex and size % 4 else None
        data = self.pack(values, ctype, kind, stride)
        if stride:  # the view ends with the last element, not with its padding
            data = data[:len(data) - (stride - size)]
        accessor = {'bufferView': self.view(data, target, stride), 'componentType': ctype,
                    'count': len(values), 'type': kind}
        if normalized:
            accessor['normalized'] = True
        if minmax:
            accessor.update(self.bounds(values, ctype))
        accessor.update(extra)
        return self.add('accessors', accessor)

    @staticmethod
    def bounds(values, ctype):
        rows = [v if isinstance(v, (tuple, list)) else (v,) for v in values]
        if ctype == FLOAT:
            rows = [[f32(x) for x in row] for row in rows]
        return {'min': [min(r[k] for r in rows) for k in range(len(rows[0]))],
                'max': [max(r[k] for r in rows) for k in range(len(rows[0]))]}

    def shared_indices(self, lists, ctype):
        """Index accessors for several triangle lists, one after the other in one buffer view."""
        data, offsets = b'', []
        for triangles in lists:
            data += b'\0' * (-len(data) % 4)
            offsets.append(len(data))
            data += self.pack(flat(triangles), ctype, 'SCALAR')
        view = self.view(data, 34963)
        return [self.add('accessors', {'bufferView': view, 'byteOffset': offset, 'componentType': ctype,
                                       'count': 3 * len(triangles), 'type': 'SCALAR'})
                for offset, triangles in zip(offsets, lists)]

    def indices(self, triangles, ctype):
        flat = [i for t in triangles for i in t]
        return self.accessor(flat, ctype, 'SCALAR', target=34963, vertex=False)

    def interleaved(self, columns, count):
        """Attributes interleaved in one view: columns = [(name, values, ctype, kind, normalized)]."""
        sizes = [struct.calcsize('<' + FMT[c] * NCOMP[k]) for _, _, c, k, _ in columns]
        padded = [(s + 3) // 4 * 4 for s in sizes]
        stride = sum(padded)
        data = bytearray()
        for v in range(count):
            for (name, values, ctype, kind, _), size, pad in zip(columns, sizes, padded):
                value = values[v] if isinstance(values[v], (tuple, list)) else (values[v],)
                data += struct.pack('<' + FMT[ctype] * NCOMP[kind], *value) + b'\0' * (pad - size)
        view = self.view(bytes(data), 34962, stride)
        out, offset = {}, 0
        for (name, values, ctype, kind, normalized), pad in zip(columns, padded):
            accessor = {'bufferView': view, 'byteOffset': offset, 'componentType': ctype, 'count': count, 'type': kind}
            if normalized:
                accessor['normalized'] = True
            if name == 'POSITION':
                accessor.update(self.bounds(values, ctype))
            out[name] = self.add('accessors', accessor)
            offset += pad
        return out

    def save(self, path, buffer='glb'):
        """buffer: 'glb' (BIN chunk), 'external' (PATH's stem + .bin beside it), 'data' (a data URI) or
        'two' (the same bytes twice, as an external .bin and as a data URI, the buffer views taking
        turns between them)."""
        j = json.loads(json.dumps(self.j))
        data = bytes(self.bin) + b'\0' * (-len(self.bin) % 4)
        if buffer == 'glb':
            j['buffers'] = [{'byteLength': len(data)}]
            text = json.dumps(j, separators=(',', ':')).encode()
            text += b' ' * (-len(text) % 4)
            body = struct.pack('<II', len(text), 0x4E4F534A) + text + struct.pack('<II', len(data), 0x004E4942) + data
            with open(path, 'wb') as out:
                out.write(struct.pack('<III', 0x46546C67, 2, 12 + len(body)) + body)
            return path
        if buffer in ('external', 'two'):
            name = os.path.splitext(os.path.basename(path))[0] + '.bin'
            with open(os.path.join(os.path.dirname(path), name), 'wb') as out:
                out.write(data)
            j['buffers'] = [{'byteLength': len(data), 'uri': name}]
            if buffer == 'two':
                j['buffers'].append({'byteLength': len(data),
                                     'uri': 'data:application/octet-stream;base64,' + base64.b64encode(data).decode()})
                for k, view in enumerate(j.get('bufferViews', [])):
                    view['buffer'] = k % 2
        else:
            j['buffers'] = [{'byteLength': len(data),
                             'uri': 'data:application/octet-stream;base64,' + base64.b64encode(data).decode()}]
        with open(path, 'w') as out:
            json.dump(j, out, indent=1)
        return path


# ------------------------------------------------------------------------------ shapes

def oriented(positions, triangles, outward):
    """Triangles wound so that their normal points along outward(triangle)."""
    out = []
    for t in triangles:
        a, b, c = (positions[i] for i in t)
        e1 = [b[k] - a[k] for k in range(3)]
        e2 = [c[k] - a[k] for k in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        d = outward(t)
        out.append(t if sum(n[k] * d[k] for k in range(3)) >= 0 else (t[0], t[2], t[1]))
    return out


def torus(nu, nv, big=1.0, small=0.4):
    positions, normals = [], []
    for i in range(nu):
        for j in range(nv):
            u, v = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            positions.append(((big + small * math.cos(v)) * math.cos(u), (big + small * math.cos(v)) * math.sin(u),
                              small * math.sin(v)))
            normals.append((math.cos(v) * math.cos(u), math.cos(v) * math.sin(u), math.sin(v)))
    triangles = []
    for i in range(nu):
        for j in range(nv):
            a, b = i * nv + j, ((i + 1) % nu) * nv + j
            c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
            triangles += [(a, b, c), (a, c, d)]
    return positions, normals, oriented(positions, triangles, lambda t: normals[t[0]])


def sphere(rings, segments, radius=1.0):
    positions = [(0.0, 0.0, radius)]
    for r in range(1, rings):
        theta = math.pi * r / rings
        for s in range(segments):
            phi = 2 * math.pi * s / segments
            positions.append((radius * math.sin(theta) * math.cos(phi), radius * math.sin(theta) * math.sin(phi),
                              radius * math.cos(theta)))
    positions.append((0.0, 0.0, -radius))
    last = len(positions) - 1
    triangles = []
    for s in range(segments):
        triangles.append((0, 1 + s, 1 + (s + 1) % segments))
        triangles.append((last, 1 + (rings - 2) * segments + s, 1 + (rings - 2) * segments + (s + 1) % segments))
    for r in range(rings - 2):
        for s in range(segments):
            a, b = 1 + r * segments + s, 1 + r * segments + (s + 1) % segments
            c, d = a + segments, b + segments
            triangles += [(a, c, d), (a, d, b)]
    normals = [tuple(x / radius for x in p) for p in positions]
    return positions, normals, oriented(positions, triangles, lambda t: positions[t[0]])


def heightfield(nx, ny, height):
    positions = [(x / (nx - 1) * 2 - 1, y / (ny - 1) * 2 - 1, 0.0) for y in range(ny) for x in range(nx)]
    positions = [(x, y, height(x, y)) for x, y, _ in positions]
    triangles = []
    for y in range(ny - 1):
        for x in range(nx - 1):
            a = y * nx + x
            triangles += [(a, a + 1, a + nx + 1), (a, a + nx + 1, a + nx)]
    normals = []
    for x, y, _ in positions:
        e = 1e-4
        gx = (height(x + e, y) - height(x - e, y)) / (2 * e)
        gy = (height(x, y + e) - height(x, y - e)) / (2 * e)
        length = math.sqrt(gx * gx + gy * gy + 1)
        normals.append((-gx / length, -gy / length, 1 / length))
    return positions, normals, triangles


def tube(around, rings, length=2.0, radius=0.3):
    positions, normals = [], []
    for r in range(rings):
        for a in range(around):
            phi = 2 * math.pi * a / around
            positions.append((radius * math.cos(phi), radius * math.sin(phi), length * r / (rings - 1)))
            normals.append((math.cos(phi), math.sin(phi), 0.0))
    triangles = []
    for r in range(rings - 1):
        for a in range(around):
            p, q = r * around + a, r * around + (a + 1) % around
            triangles += [(p, q, q + around), (p, q + around, p + around)]
    return positions, normals, oriented(positions, triangles, lambda t: normals[t[0]])


def uv_of(positions, scale=1.0):
    return [((p[0] * 0.3 + 0.5) * scale, (p[1] * 0.3 + 0.5) * scale) for p in positions]


def flat(triangles):
    return [i for t in triangles for i in t]


# ------------------------------------------------------------------------------ the generated files

def material(doc, name, texture=None):
    m = {'name': name, 'pbrMetallicRoughness': {'baseColorFactor': [0.8, 0.5, 0.2, 1.0], 'metallicFactor': 0.1},
         'doubleSided': False, 'extras': {'material': name}}
    if texture is not None:
        m['pbrMetallicRoughness']['baseColorTexture'] = {'index': texture, 'texCoord': 0}
    return doc.add('materials', m)


def png_texture(doc):
    image = doc.add('images', {'bufferView': doc.view(png_bytes(2, 2, (200, 30, 90))), 'mimeType': 'image/png',
                               'name': 'swatch'})
    sampler = doc.add('samplers', {'magFilter': 9729, 'minFilter': 9987, 'wrapS': 33648})
    return doc.add('textures', {'source': image, 'sampler': sampler})


def scene_of(doc, nodes):
    doc.j['scenes'] = [{'nodes': nodes, 'name': 'the scene', 'extras': {'scene': 1}}]
    doc.j['scene'] = 0


def gen_skinned(folder):
    doc = Doc()
    positions, normals, triangles = tube(12, 9)
    joints, weights, colors = [], [], []
    for p in positions:
        w = f32(min(max(p[2] / 2.0, 0.0), 1.0))
        if 0.0 < w < 1.0:
            joints.append((0, 1, 0, 0))
            weights.append((f32(1.0 - w), w, 0.0, 0.0))
        else:
            joints.append((int(w), 0, 0, 0))
            weights.append((1.0, 0.0, 0.0, 0.0))
        colors.append((int(p[2] * 30000) % 65536, 40000, 1000))
    attributes = {
        'POSITION': doc.accessor(positions, FLOAT, 'VEC3', target=34962, minmax=True),
        'NORMAL': doc.accessor(normals, FLOAT, 'VEC3', target=34962),
        'JOINTS_0': doc.accessor(joints, U8, 'VEC4', target=34962),
        'WEIGHTS_0': doc.accessor(weights, FLOAT, 'VEC4', target=34962),
        'COLOR_0': doc.accessor(colors, U16, 'VEC3', normalized=True, target=34962),
    }
    # The same tube beside it with 16-bit joints and weights in normalized bytes.
    joints16, weights8 = [], []
    for p in positions:
        k = int(round(min(max(p[2] / 2.0, 0.0), 1.0) * 255))
        joints16.append((0, 1, 0, 0) if 0 < k < 255 else (k // 255, 0, 0, 0))
        weights8.append((255 - k, k, 0, 0) if 0 < k < 255 else (255, 0, 0, 0))
    moved = [(x + 1, y, z) for x, y, z in positions]
    attributes2 = {
        'POSITION': doc.accessor(moved, FLOAT, 'VEC3', target=34962, minmax=True),
        'JOINTS_0': doc.accessor(joints16, U16, 'VEC4', target=34962),
        'WEIGHTS_0': doc.accessor(weights8, U8, 'VEC4', normalized=True, target=34962)}
    doc.add('meshes', {'name': 'arm', 'primitives': [
        {'attributes': attributes, 'indices': doc.indices(triangles, U16), 'material': material(doc, 'skin'),
         'extras': {'primitive': 'arm'}},
        {'attributes': attributes2, 'indices': doc.indices(triangles, U8 if len(moved) < 255 else U16)}],
        'extras': {'mesh': 'arm'}})
    inverse = [(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1), (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -1, 1)]
    doc.add('nodes', {'name': 'arm', 'mesh': 0, 'skin': 0})
    doc.add('nodes', {'name': 'shoulder', 'children': [2], 'translation': [0, 0, 0]})
    doc.add('nodes', {'name': 'elbow', 'translation': [0, 0, 1], 'rotation': [0, 0, 0, 1], 'extras': {'joint': 1}})
    doc.add('skins', {'name': 'rig', 'joints': [1, 2], 'skeleton': 1,
                      'inverseBindMatrices': doc.accessor(inverse, FLOAT, 'MAT4', vertex=False)})
    times = [0.0, 0.5, 1.0]
    rotations = [(0, 0, 0, 1), (math.sin(0.4), 0, 0, math.cos(0.4)), (0, 0, 0, 1)]
    steps = [(0, 0, 1), (0, 0.1, 1), (0, 0, 1)]
    time_accessor = doc.accessor(times, FLOAT, 'SCALAR', minmax=True, vertex=False)
    doc.add('animations', {'name': 'bend', 'samplers': [
        {'input': time_accessor, 'output': doc.accessor(rotations, FLOAT, 'VEC4', vertex=False), 'interpolation': 'LINEAR'},
        {'input': time_accessor, 'output': doc.accessor(steps, FLOAT, 'VEC3', vertex=False), 'interpolation': 'STEP'}],
        'channels': [{'sampler': 0, 'target': {'node': 2, 'path': 'rotation'}},
                     {'sampler': 1, 'target': {'node': 2, 'path': 'translation'}}], 'extras': {'clip': 'bend'}})
    scene_of(doc, [0, 1])
    return doc.save(os.path.join(folder, 'skinned.glb'))


def gen_morph(folder):
    doc = Doc()
    positions, normals, triangles = sphere(10, 16)
    d1 = [(0.0, 0.0, 0.2 * max(p[2], 0.0)) for p in positions]
    d2 = [(0.1 * p[0], 0.0, 0.0) for p in positions]
    n1 = [(0.0, 0.01 * i % 0.05, 0.0) for i in range(len(positions))]
    n2 = [(0.02, 0.0, -0.01) for _ in positions]
    tangents = []
    for x, y, _ in positions:
        length = math.hypot(x, y)
        tangents.append((-y / length, x / length, 0.0, 1.0) if length > 1e-9 else (1.0, 0.0, 0.0, -1.0))
    t2 = [(0.0, 0.0, 0.001 * (i % 4)) for i in range(len(positions))]
    targets = [{'POSITION': doc.accessor(d1, FLOAT, 'VEC3', target=34962, minmax=True),
                'NORMAL': doc.accessor(n1, FLOAT, 'VEC3', target=34962)},
               {'POSITION': doc.accessor(d2, FLOAT, 'VEC3', target=34962, minmax=True),
                'NORMAL': doc.accessor(n2, FLOAT, 'VEC3', target=34962),
                'TANGENT': doc.accessor(t2, FLOAT, 'VEC3', target=34962)}]
    attributes = {'POSITION': doc.accessor(positions, FLOAT, 'VEC3', target=34962, minmax=True),
                  'NORMAL': doc.accessor(normals, FLOAT, 'VEC3', target=34962),
                  'TANGENT': doc.accessor(tangents, FLOAT, 'VEC4', target=34962)}
    doc.add('meshes', {'name': 'blob', 'weights': [0.25, 0.5], 'extras': {'targetNames': ['bulge', 'widen']},
                       'primitives': [{'attributes': attributes, 'targets': targets,
                                       'indices': doc.indices(triangles, U16), 'material': material(doc, 'blob')}]})
    doc.add('nodes', {'name': 'blob', 'mesh': 0, 'weights': [0.1, 0.2]})
    times = doc.accessor([0.0, 1.0], FLOAT, 'SCALAR', minmax=True, vertex=False)
    doc.add('animations', {'samplers': [{'input': times, 'output': doc.accessor([0.0, 0.0, 1.0, 0.5], FLOAT, 'SCALAR', vertex=False)}],
                           'channels': [{'sampler': 0, 'target': {'node': 0, 'path': 'weights'}}]})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'morph.glb'))


def gen_sparse(folder):
    doc = Doc()
    positions, normals, triangles = heightfield(12, 10, lambda x, y: 0.2 * math.sin(2 * x) * math.cos(2 * y))
    changed = list(range(5, len(positions), 9))
    final = list(positions)
    for i in changed:
        final[i] = (positions[i][0], positions[i][1], positions[i][2] + 0.05)
    position = doc.accessor(positions, FLOAT, 'VEC3', target=34962)
    doc.j['accessors'][position].update(doc.bounds(final, FLOAT))
    doc.j['accessors'][position]['sparse'] = {
        'count': len(changed),
        'indices': {'bufferView': doc.view(doc.pack(changed, U16, 'SCALAR')), 'componentType': U16},
        'values': {'bufferView': doc.view(doc.pack([final[i] for i in changed], FLOAT, 'VEC3'))}}
    # A morph target of zeros but for its sparse substitutions (no buffer view at all).
    bumped = list(range(0, len(positions), 7))
    deltas = [(0.0, 0.0, 0.0)] * len(positions)
    for i in bumped:
        deltas[i] = (0.0, 0.0, f32(0.01 * (i % 5)))
    target = doc.add('accessors', {'componentType': FLOAT, 'count': len(positions), 'type': 'VEC3',
                                   'sparse': {'count': len(bumped),
                                              'indices': {'bufferView': doc.view(doc.pack(bumped, U8, 'SCALAR')), 'componentType': U8},
                                              'values': {'bufferView': doc.view(doc.pack([deltas[i] for i in bumped], FLOAT, 'VEC3'))}}})
    doc.j['accessors'][target].update(doc.bounds(deltas, FLOAT))
    attributes = {'POSITION': position, 'NORMAL': doc.accessor(normals, FLOAT, 'VEC3', target=34962)}
    doc.add('meshes', {'name': 'sparse', 'primitives': [{'attributes': attributes, 'targets': [{'POSITION': target}],
                                                         'indices': doc.indices(triangles, U16)}], 'weights': [0.0]})
    doc.add('nodes', {'mesh': 0})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'sparse.glb'))


def gen_normalized_uv(folder):
    doc = Doc()
    texture = png_texture(doc)
    mat = material(doc, 'textured', texture)
    primitives = []
    # u8 indices and u8 texture coordinates; 252 vertices, which the seams push past 255.
    p, n, t = torus(14, 18)
    primitives.append({'attributes': {
        'POSITION': doc.accessor(p, FLOAT, 'VEC3', target=34962, minmax=True),
        'NORMAL': doc.accessor(n, FLOAT, 'VEC3', target=34962),
        'TEXCOORD_0': doc.accessor([(int(u * 255) % 256, int(v * 255) % 256) for u, v in uv_of(p)], U8, 'VEC2',
                                   normalized=True, target=34962)},
        'indices': doc.indices(t, U8), 'material': mat})
    # u16 texture coordinates, u16 indices.
    p, n, t = sphere(8, 12, 0.5)
    p = [(x + 3, y, z) for x, y, z in p]
    primitives.append({'attributes': {
        'POSITION': doc.accessor(p, FLOAT, 'VEC3', target=34962, minmax=True),
        'NORMAL': doc.accessor(n, FLOAT, 'VEC3', target=34962),
        'TEXCOORD_0': doc.accessor([(int(u * 20000) % 65536, int(v * 20000) % 65536) for u, v in uv_of(p)], U16, 'VEC2',
                                   normalized=True, target=34962)},
        'indices': doc.indices(t, U16), 'material': mat})
    # Few vertices under u8 indices (they stay u8), and no texture coordinates (the atlas: TEXCOORD_0).
    p, n, t = sphere(4, 6, 0.5)
    p = [(x - 3, y, z) for x, y, z in p]
    primitives.append({'attributes': {'POSITION': doc.accessor(p, FLOAT, 'VEC3', target=34962, minmax=True)},
                       'indices': doc.indices(t, U8)})
    doc.add('meshes', {'name': 'three parts', 'primitives': primitives})
    doc.add('nodes', {'mesh': 0, 'name': 'parts'})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'normalized_uv.glb'))


def gen_big_u16(folder):
    doc = Doc()
    p, n, t = torus(256, 254)
    assert len(p) <= 65535
    doc.add('meshes', {'name': 'big torus', 'primitives': [{'attributes': {
        'POSITION': doc.accessor(p, FLOAT, 'VEC3', target=34962, minmax=True),
        'NORMAL': doc.accessor(n, FLOAT, 'VEC3', target=34962)}, 'indices': doc.indices(t, U16)}]})
    doc.add('nodes', {'mesh': 0})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'big_u16.glb'))


def gen_instanced(folder):
    doc = Doc()
    p, n, t = heightfield(9, 7, lambda x, y: 0.3 * math.sin(2.5 * x + 0.5) * math.cos(1.5 * y) + 0.2 * x * y)
    doc.add('meshes', {'name': 'placed twice', 'primitives': [{'attributes': {
        'POSITION': doc.accessor(p, FLOAT, 'VEC3', target=34962, minmax=True),
        'NORMAL': doc.accessor(n, FLOAT, 'VEC3', target=34962)}, 'indices': doc.indices(t, U16)}]})
    q, m, s = sphere(6, 8, 0.4)
    doc.add('meshes', {'name': 'under a parent', 'primitives': [{'attributes': {
        'POSITION': doc.accessor(q, FLOAT, 'VEC3', target=34962, minmax=True)}, 'indices': doc.indices(s, U16)}]})
    doc.add('nodes', {'name': 'mirrored', 'mesh': 0, 'scale': [-1, 1, 1], 'translation': [-3, 0, 0]})
    doc.add('nodes', {'name': 'plain', 'mesh': 0, 'translation': [3, 0, 0]})
    doc.add('nodes', {'name': 'parent', 'matrix': [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 5, 0, 1], 'children': [3]})
    doc.add('nodes', {'name': 'child', 'mesh': 1, 'rotation': [0, 0, math.sin(0.3), math.cos(0.3)]})
    # The default scene is the second: there the mirrored node places the mesh first.
    doc.j['scenes'] = [{'nodes': [1], 'name': 'plain only'}, {'nodes': [0, 1, 2], 'name': 'both'}]
    doc.j['scene'] = 1
    return doc.save(os.path.join(folder, 'instanced.glb'))


def simple_mesh(doc, name='torus'):
    p, n, t = torus(10, 8)
    return doc.add('meshes', {'name': name, 'primitives': [{'attributes': {
        'POSITION': doc.accessor(p, FLOAT, 'VEC3', target=34962, minmax=True),
        'NORMAL': doc.accessor(n, FLOAT, 'VEC3', target=34962),
        'TEXCOORD_0': doc.accessor(uv_of(p), FLOAT, 'VEC2', target=34962)}, 'indices': doc.indices(t, U16),
        'material': material(doc, name)}]})


def gen_empty_scene(folder):
    doc = Doc()
    simple_mesh(doc)
    doc.add('nodes', {'mesh': 0, 'name': 'not in the scene'})
    doc.j['scenes'] = [{'name': 'empty'}, {'nodes': [0]}]
    doc.j['scene'] = 0
    return doc.save(os.path.join(folder, 'empty_scene.glb'))


def gen_no_scene(folder):
    doc = Doc()
    simple_mesh(doc)
    return doc.save(os.path.join(folder, 'no_scene.glb'))


def gen_interleaved(folder):
    doc = Doc()
    p, n, t = torus(12, 10)
    colors = [(int(128 + 120 * x), int(128 + 100 * y), 30, 255) for x, y, z in [(a / 1.4, b / 1.4, c) for a, b, c in p]]
    ids = doc.interleaved([('POSITION', p, FLOAT, 'VEC3', False), ('NORMAL', n, FLOAT, 'VEC3', False),
                           ('TEXCOORD_0', uv_of(p), FLOAT, 'VEC2', False), ('COLOR_0', colors, U8, 'VEC4', True)], len(p))
    ids['_FOO'] = doc.accessor([(i % 7, i // 7) for i in range(len(p))], U16, 'VEC2', target=34962)
    ids['TEXCOORD_1'] = doc.accessor(uv_of(p, 0.5), FLOAT, 'VEC2', target=34962)
    doc.add('meshes', {'name': 'interleaved', 'primitives': [{'attributes': ids, 'indices': doc.indices(t, U32),
                                                              'material': material(doc, 'painted')}]})
    doc.add('nodes', {'mesh': 0})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'interleaved.glb'))


def gen_strip_fan(folder):
    doc = Doc()
    nx, ny = 8, 4
    p = [(x * 0.5, y * 0.5, 0.1 * math.sin(x) * math.cos(y)) for y in range(ny) for x in range(nx)]
    strip = []
    for y in range(ny - 1):
        row = []
        for x in range(nx):
            row += [y * nx + x, (y + 1) * nx + x]
        if strip:
            strip += [strip[-1], row[0]]  # stitching: four degenerate triangles, parity kept
        strip += row
    primitives = [{'attributes': {'POSITION': doc.accessor(p, FLOAT, 'VEC3', target=34962, minmax=True),
                                  'TEXCOORD_0': doc.accessor(uv_of(p), FLOAT, 'VEC2', target=34962)},
                   'indices': doc.accessor(strip, U16, 'SCALAR', target=34963, vertex=False), 'mode': 5}]
    # A cone as an indexed fan (apex, then the ring closed by repeating its first vertex).
    ring = 14
    cone = [(0.0, 0.0, 1.0)] + [(math.cos(2 * math.pi * k / ring), math.sin(2 * math.pi * k / ring), 0.0) for k in range(ring)]
    cone = [(x + 6, y, z) for x, y, z in cone]
    primitives.append({'attributes': {'POSITION': doc.accessor(cone, FLOAT, 'VEC3', target=34962, minmax=True)},
                       'indices': doc.accessor([0] + list(range(1, ring + 1)) + [1], U8, 'SCALAR', target=34963, vertex=False),
                       'mode': 6})
    # The same cone as a fan without indices, then a strip without indices.
    flat_cone = [(x, y + 3, z) for x, y, z in cone] + [(cone[1][0], cone[1][1] + 3, cone[1][2])]
    primitives.append({'attributes': {'POSITION': doc.accessor(flat_cone, FLOAT, 'VEC3', target=34962, minmax=True)},
                       'mode': 6})
    ribbon = [(x * 0.4, -3 + (x % 2) * 0.6, 0.05 * x * x) for x in range(16)]
    primitives.append({'attributes': {'POSITION': doc.accessor(ribbon, FLOAT, 'VEC3', target=34962, minmax=True)},
                       'mode': 5})
    # Lines and points: no triangles, left as they are.
    primitives.append({'attributes': {'POSITION': primitives[0]['attributes']['POSITION']},
                       'indices': doc.accessor([0, 1, 1, 2, 2, 3], U16, 'SCALAR', target=34963, vertex=False), 'mode': 1})
    dots = [(0.0, 0.0, 2.0), (1.0, 0.0, 2.0), (0.0, 1.0, 2.0)]
    primitives.append({'attributes': {'POSITION': doc.accessor(dots, FLOAT, 'VEC3', target=34962, minmax=True)}, 'mode': 0})
    doc.add('meshes', {'name': 'strips and fans', 'primitives': primitives})
    doc.add('nodes', {'mesh': 0})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'strip_fan.glb'))


def gen_external(folder):
    doc = Doc()
    simple_mesh(doc)
    doc.add('nodes', {'mesh': 0})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'external.gltf'), 'external')


def gen_data_uri(folder):
    doc = Doc()
    simple_mesh(doc)
    doc.add('nodes', {'mesh': 0})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'data_uri.gltf'), 'data')


def gen_shared(folder):
    """Two primitives over one set of vertex accessors (as exporters write multi-material meshes),
    a triangle list without indices, extensions on primitives, nodes and the document (variants,
    lights, GPU instancing), a camera, and an accessor and a buffer view nothing refers to."""
    doc = Doc()
    p, n, t = torus(12, 10)
    attributes = {'POSITION': doc.accessor(p, FLOAT, 'VEC3', target=34962, minmax=True),
                  'NORMAL': doc.accessor(n, FLOAT, 'VEC3', target=34962),
                  'TEXCOORD_0': doc.accessor(uv_of(p), FLOAT, 'VEC2', target=34962)}
    red, blue = material(doc, 'red'), material(doc, 'blue')
    half = len(t) // 2
    first, second = doc.shared_indices([t[:half], t[half:]], U16)
    primitives = [{'attributes': attributes, 'indices': first, 'material': red,
                   'extensions': {'KHR_materials_variants': {'mappings': [{'material': blue, 'variants': [0]}]}}},
                  {'attributes': dict(attributes), 'indices': second, 'material': blue}]
    q, _, s = sphere(5, 8, 0.5)
    soup = [(q[i][0] + 3, q[i][1], q[i][2]) for tri in s for i in tri]
    primitives.append({'attributes': {'POSITION': doc.accessor(soup, FLOAT, 'VEC3', target=34962, minmax=True)},
                       'material': red})
    doc.add('meshes', {'name': 'shared vertices', 'primitives': primitives})
    doc.add('meshes', {'name': 'the same accessors', 'primitives': [
        {'attributes': dict(attributes), 'indices': primitives[0]['indices'], 'material': blue}]})
    doc.accessor([(1.0, 2.0)] * 5, FLOAT, 'VEC2')  # nothing refers to it
    doc.view(b'unused view!')
    offsets = doc.accessor([(0.0, 0.0, 0.0), (0.0, 4.0, 0.0), (0.0, 8.0, 0.0)], FLOAT, 'VEC3', vertex=False)
    doc.add('nodes', {'mesh': 0, 'extensions': {'EXT_mesh_gpu_instancing': {'attributes': {'TRANSLATION': offsets}}}})
    doc.add('nodes', {'name': 'lamp', 'translation': [0, 0, 5], 'extensions': {'KHR_lights_punctual': {'light': 0}}})
    doc.add('nodes', {'name': 'eye', 'camera': 0, 'translation': [0, -10, 0], 'rotation': [math.sin(0.785), 0, 0, math.cos(0.785)]})
    doc.add('nodes', {'mesh': 1, 'translation': [0, 0, -4]})
    doc.j['cameras'] = [{'type': 'perspective', 'perspective': {'yfov': 0.8, 'znear': 0.1, 'zfar': 100}}]
    doc.j['extensionsUsed'] = ['KHR_materials_variants', 'KHR_lights_punctual', 'EXT_mesh_gpu_instancing']
    doc.j['extensions'] = {'KHR_materials_variants': {'variants': [{'name': 'blue'}]},
                           'KHR_lights_punctual': {'lights': [{'type': 'point', 'color': [1, 0.9, 0.8], 'intensity': 3}]}}
    scene_of(doc, [0, 1, 2, 3])
    return doc.save(os.path.join(folder, 'shared.glb'))


def gen_external_image(folder):
    """A .gltf with its buffer and its image in files beside it."""
    doc = Doc()
    with open(os.path.join(folder, 'swatch.png'), 'wb') as out:
        out.write(png_bytes(2, 2, (20, 200, 90)))
    image = doc.add('images', {'uri': 'swatch.png'})
    texture = doc.add('textures', {'source': image})
    mesh = simple_mesh(doc)
    doc.j['materials'][doc.j['meshes'][mesh]['primitives'][0]['material']]['pbrMetallicRoughness']['baseColorTexture'] = {
        'index': texture}
    doc.add('nodes', {'mesh': 0})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'external_image.gltf'), 'external')


def gen_two_buffers(folder):
    doc = Doc()
    simple_mesh(doc)
    simple_mesh(doc, 'another')
    doc.add('nodes', {'mesh': 0})
    doc.add('nodes', {'mesh': 1, 'translation': [0, 0, 3]})
    scene_of(doc, [0, 1])
    return doc.save(os.path.join(folder, 'two_buffers.gltf'), 'two')


def gen_quantized(folder):
    """KHR_mesh_quantization: 16-bit integer positions (the node scales them), normals in
    normalized bytes, texture coordinates in normalized 16-bit integers."""
    doc = Doc()
    p, n, t = torus(14, 10)
    ip = [tuple(int(round(x * 1000)) for x in v) for v in p]
    inormal = [tuple(int(round(x * 127)) for x in v) for v in n]
    iuv = [(int(u * 30000), int(v * 30000)) for u, v in uv_of(p)]
    doc.add('meshes', {'name': 'quantized', 'primitives': [{'attributes': {
        'POSITION': doc.accessor(ip, I16, 'VEC3', target=34962, minmax=True),
        'NORMAL': doc.accessor(inormal, I8, 'VEC3', normalized=True, target=34962),
        'TEXCOORD_0': doc.accessor(iuv, I16, 'VEC2', normalized=True, target=34962)},
        'indices': doc.indices(t, U16), 'material': material(doc, 'quantized')}]})
    doc.add('nodes', {'mesh': 0, 'scale': [0.001, 0.001, 0.001]})
    doc.j['extensionsUsed'] = ['KHR_mesh_quantization']
    doc.j['extensionsRequired'] = ['KHR_mesh_quantization']
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'quantized.glb'))


def gen_overrun(folder):
    """POSITION's accessor counts more vertices than its buffer view holds."""
    doc = Doc()
    simple_mesh(doc)
    doc.j['accessors'][doc.j['meshes'][0]['primitives'][0]['attributes']['POSITION']]['count'] += 40
    doc.add('nodes', {'mesh': 0})
    scene_of(doc, [0])
    return doc.save(os.path.join(folder, 'overrun.gltf'), 'data')


GENERATORS = {'skinned': gen_skinned, 'morph': gen_morph, 'sparse': gen_sparse, 'normalized_uv': gen_normalized_uv,
              'big_u16': gen_big_u16, 'instanced': gen_instanced, 'empty_scene': gen_empty_scene,
              'no_scene': gen_no_scene, 'interleaved': gen_interleaved, 'strip_fan': gen_strip_fan,
              'external': gen_external, 'data_uri': gen_data_uri, 'shared': gen_shared,
              'external_image': gen_external_image, 'two_buffers': gen_two_buffers,
              'quantized': gen_quantized, 'overrun': gen_overrun}


# ------------------------------------------------------------------------------ the runs

class Run:
    """One `harmonia atlas` run; `source` is a corpus file name, 'gen:<generator>' or 'run:<the
    run whose output it takes>'; the output is STEM + suffix in a folder of the run's own."""

    def __init__(self, name, source, suffix='.glb', options=(), stem='out'):
        self.name, self.source, self.suffix, self.options, self.stem = name, source, suffix, list(options), stem
        self.result = None


RUNS = [
    Run('BoxInterleaved', 'BoxInterleaved.glb'),
    Run('CesiumMilkTruck', 'CesiumMilkTruck.glb'),
    Run('CesiumMilkTruck_primitive', 'CesiumMilkTruck.glb', options=['--group', 'primitive']),
    Run('CesiumMilkTruck_scene_gltf', 'CesiumMilkTruck.glb', '.gltf', ['--group', 'scene']),
    Run('CesiumMilkTruck_mesh1', 'CesiumMilkTruck.glb', options=['--mesh', '1']),
    Run('DamagedHelmet', 'DamagedHelmet.glb'),
    Run('Duck', 'Duck.glb'),
    Run('Duck_gltf', 'Duck.glb', '.gltf'),
    Run('Duck_gltf_odd_name', 'Duck.glb', '.gltf', stem='my duck #1 (50% off)'),
    Run('Duck_overwrite0', 'Duck.glb', options=['--texcoord', '0', '--overwrite']),
    Run('TestScene', 'TestScene.gltf'),
    Run('TestScene_gltf', 'TestScene.gltf', '.gltf'),
    Run('cubevc', 'cubevc.glb'),
    # 54 atlases: judged at 256 texels a side to keep atlaseval (pure Python) quick.
    Run('mode5', 'mode5.gltf'),
    Run('mode5_scene', 'mode5.gltf', options=['--group', 'scene']),
    Run('pirate', 'pirate.glb'),
    Run('gen_skinned', 'gen:skinned'),
    Run('gen_morph', 'gen:morph'),
    Run('gen_sparse', 'gen:sparse'),
    Run('gen_normalized_uv', 'gen:normalized_uv'),
    Run('gen_normalized_uv_primitive', 'gen:normalized_uv', options=['--group', 'primitive']),
    Run('gen_big_u16', 'gen:big_u16'),
    Run('gen_instanced', 'gen:instanced'),
    Run('gen_instanced_scene', 'gen:instanced', options=['--group', 'scene']),
    Run('gen_instanced_mesh_by_name', 'gen:instanced', options=['--mesh', 'under a parent']),
    Run('gen_empty_scene', 'gen:empty_scene'),
    Run('gen_empty_scene_scene', 'gen:empty_scene', options=['--group', 'scene']),
    Run('gen_no_scene', 'gen:no_scene'),
    Run('gen_no_scene_primitive', 'gen:no_scene', options=['--group', 'primitive']),
    Run('gen_shared', 'gen:shared'),
    Run('gen_shared_mesh0', 'gen:shared', options=['--mesh', '0']),
    Run('gen_shared_primitive', 'gen:shared', '.gltf', ['--group', 'primitive']),
    Run('gen_interleaved', 'gen:interleaved'),
    Run('gen_interleaved_texcoord2', 'gen:interleaved', '.gltf', ['--texcoord', '2']),
    Run('gen_strip_fan', 'gen:strip_fan'),
    Run('gen_external', 'gen:external'),
    Run('gen_external_gltf', 'gen:external', '.gltf'),
    Run('gen_data_uri_gltf', 'gen:data_uri', '.gltf'),
    Run('gen_data_uri', 'gen:data_uri'),
    Run('gen_external_image', 'gen:external_image'),
    Run('gen_external_image_gltf', 'gen:external_image', '.gltf'),
    Run('gen_two_buffers', 'gen:two_buffers'),
    Run('gen_quantized', 'gen:quantized'),
    Run('gen_two_buffers_gltf', 'gen:two_buffers', '.gltf'),
    # Again on its own output: a third set, and _CHART made afresh.
    Run('rerun_Duck', 'run:Duck'),
    Run('rerun_gen_morph_gltf', 'run:gen_morph', '.gltf'),
]


class Scratch:
    folder = None
    generated = {}

    @classmethod
    def path(cls, *parts):
        if cls.folder is None:
            cls.folder = tempfile.mkdtemp(prefix='harmonia-gltf-files-')
            atexit.register(cls.cleanup)
            if os.environ.get('HARMONIA_KEEP_TEST_FILES'):
                print('test files in', cls.folder, file=sys.stderr)
        return os.path.join(cls.folder, *parts)

    @classmethod
    def cleanup(cls):
        if cls.folder and not os.environ.get('HARMONIA_KEEP_TEST_FILES'):
            shutil.rmtree(cls.folder, ignore_errors=True)


def source_path(source):
    """The input file of a run (generated once), or a skip/failure without the corpus."""
    if source.startswith('run:'):  # the output of another run
        return perform(next(run for run in RUNS if run.name == source[4:])).output
    if source.startswith('gen:'):
        key = source[4:]
        if key not in Scratch.generated:
            folder = Scratch.path('in-' + key)
            os.makedirs(folder, exist_ok=True)
            Scratch.generated[key] = GENERATORS[key](folder)
        return Scratch.generated[key]
    path = os.path.join(CORPUS, source)
    if not os.path.isfile(path):
        missing('the corpus file %s is missing' % path)
    return path


def load(path):
    """gltfread.load, but a buffer's relative URI is percent-decoded (RFC 3986) before it is
    opened: gltfread opens the URI's text as a file name, which fails on "my%20model.bin"."""
    with warnings.catch_warnings():  # gltfread leaves its file to the garbage collector
        warnings.simplefilter('ignore', ResourceWarning)
        with open(path, 'rb') as data:
            head = data.read(4)
        if head == b'glTF':
            return gltfread.load(path)
        with open(path, encoding='utf-8') as text:
            document = json.load(text)
        buffers = []
        for buffer in document.get('buffers', []):
            uri = buffer.get('uri', '')
            if uri.startswith('data:'):
                buffers.append(base64.b64decode(uri.split(',', 1)[1]))
            else:
                with open(os.path.join(os.path.dirname(path), urllib.parse.unquote(uri)), 'rb') as data:
                    buffers.append(data.read())
        return document, buffers


def harmonia(*arguments):
    return subprocess.run([CLI] + [str(a) for a in arguments], capture_output=True, text=True, timeout=300)


class Result:
    pass


def perform(run):
    """Runs harmonia once per Run; the decoded input and output are kept on it."""
    if run.result is not None:
        if isinstance(run.result, BaseException):
            raise run.result
        return run.result
    need_tools()
    try:
        r = Result()
        r.input = source_path(run.source)
        folder = Scratch.path('out-' + run.name)
        os.makedirs(folder, exist_ok=True)
        r.output = os.path.join(folder, run.stem + run.suffix)
        done = harmonia('atlas', r.input, r.output, '--json', *run.options)
        r.stdout, r.stderr, r.returncode = done.stdout, done.stderr, done.returncode
        if done.returncode != 0:
            raise AssertionError('harmonia atlas %s %s %s exited %d: %s' % (
                run.source, r.output, ' '.join(run.options), done.returncode, done.stderr.strip()[-2000:]))
        r.report = json.loads(done.stdout)
        r.jin, r.bin_in = load(r.input)
        r.jout, r.bin_out = load(r.output)
        r.tin = gltfread.triangles(r.jin, r.bin_in)
        r.tout = gltfread.triangles(r.jout, r.bin_out)
        run.result = r
    except unittest.SkipTest:
        raise
    except BaseException as error:  # noqa: B902 - kept to answer every later test of the run alike
        run.result = error
        raise
    return r


# ------------------------------------------------------------------------------ what the runs must hold

URI_PATH = re.compile(r"(?:[A-Za-z0-9\-._~!$&'()*+,;=@]|%[0-9A-Fa-f]{2})(?:[A-Za-z0-9\-._~!$&'()*+,;=:@/]|%[0-9A-Fa-f]{2})*")


def option(run, name, default=None):
    return run.options[run.options.index(name) + 1] if name in run.options else default


def selected_meshes(run, j):
    chosen = option(run, '--mesh')
    if chosen is None:
        return set(range(len(j.get('meshes', []))))
    if chosen.isdigit():
        return {int(chosen)}
    return {i for i, m in enumerate(j['meshes']) if m.get('name') == chosen}


def is_triangles(primitive):
    return primitive.get('mode', 4) in (4, 5, 6)


def rewritten(run, j):
    """(mesh, primitive) pairs the run rewrites: the triangle primitives of the chosen meshes."""
    return [(m, p) for m in sorted(selected_meshes(run, j)) for p, prim in enumerate(j['meshes'][m]['primitives'])
            if is_triangles(prim)]


def expected_set(run, primitive_json):
    chosen = option(run, '--texcoord')
    if chosen is not None:
        return 'TEXCOORD_%s' % chosen
    n = 0
    while 'TEXCOORD_%d' % n in primitive_json['attributes']:
        n += 1
    return 'TEXCOORD_%d' % n


def input_triangles(primitive):
    """gltfread's triangles, without the strips' and fans' triangles that repeat an index."""
    corners = primitive['corners']
    if primitive['mode'] in (5, 6):
        corners = [t for t in corners if len(set(t)) == 3]
    return corners


def decoded(j, bufs, index):
    return gltfread.accessor(j, bufs, index)


def view_bytes(j, bufs, index):
    v = j['bufferViews'][index]
    return bufs[v['buffer']][v.get('byteOffset', 0):v.get('byteOffset', 0) + v['byteLength']]


def references(j):
    """The accessors and buffer views the document refers to."""
    accessors, views = set(), set()
    for mesh in j.get('meshes', []):
        for prim in mesh.get('primitives', []):
            accessors.update(prim.get('attributes', {}).values())
            if 'indices' in prim:
                accessors.add(prim['indices'])
            for target in prim.get('targets', []):
                accessors.update(target.values())
            draco = prim.get('extensions', {}).get('KHR_draco_mesh_compression')
            if draco and 'bufferView' in draco:
                views.add(draco['bufferView'])
    for skin in j.get('skins', []):
        if 'inverseBindMatrices' in skin:
            accessors.add(skin['inverseBindMatrices'])
    for animation in j.get('animations', []):
        for sampler in animation.get('samplers', []):
            accessors.update((sampler['input'], sampler['output']))
    for node in j.get('nodes', []):
        accessors.update(node.get('extensions', {}).get('EXT_mesh_gpu_instancing', {}).get('attributes', {}).values())
    for image in j.get('images', []):
        if 'bufferView' in image:
            views.add(image['bufferView'])
    for a in accessors:
        accessor = j['accessors'][a]
        if 'bufferView' in accessor:
            views.add(accessor['bufferView'])
        sparse = accessor.get('sparse')
        if sparse:
            views.update((sparse['indices']['bufferView'], sparse['values']['bufferView']))
    return accessors, views


def document_view(j, bufs, folder, compressed_views=False):
    """The document's JSON outside meshes, accessors, buffer views and buffers, with every
    reference to an accessor or a buffer view replaced by what it holds, and images' relative URIs
    by the file they name (a writer in another folder must make them reach the same file)."""
    out = {k: json.loads(json.dumps(v)) for k, v in j.items()
           if k not in ('meshes', 'accessors', 'bufferViews', 'buffers', 'extensionsUsed', 'extensionsRequired')}
    for skin in out.get('skins', []):
        if 'inverseBindMatrices' in skin:
            skin['inverseBindMatrices'] = 'accessor' if compressed_views else decoded(j, bufs, skin['inverseBindMatrices'])
    for animation in out.get('animations', []):
        for sampler in animation.get('samplers', []):
            for key in ('input', 'output'):
                if compressed_views:
                    sampler[key] = 'accessor'
                else:
                    sampler[key] = decoded(j, bufs, sampler[key])
    for node in out.get('nodes', []):
        instancing = node.get('extensions', {}).get('EXT_mesh_gpu_instancing')
        if instancing and not compressed_views:
            instancing['attributes'] = {k: decoded(j, bufs, v) for k, v in instancing.get('attributes', {}).items()}
    for image in out.get('images', []):
        if 'bufferView' in image:
            image['bufferView'] = hashlib.sha256(view_bytes(j, bufs, image['bufferView'])).hexdigest()
        uri = image.get('uri', '')
        if uri.startswith('data:'):
            image['uri'] = hashlib.sha256(base64.b64decode(uri.split(',', 1)[1])).hexdigest()
        elif uri and '://' not in uri:
            image['uri'] = os.path.normpath(os.path.join(folder, urllib.parse.unquote(uri)))
    return json.loads(json.dumps(out))


def uses_meshopt(j):
    return any('EXT_meshopt_compression' in v.get('extensions', {}) for v in j.get('bufferViews', []))


def signature(prim, names, targets, vertex):
    return (tuple(prim['attributes'][n][vertex] for n in names),
            tuple(tuple(t[n][vertex] for n in sorted(t)) for t in targets))


def world_matrices(j):
    """The world matrix of the first node of the default scene (depth first) that places each
    mesh; meshes no node of that scene places keep the identity."""
    def multiply(a, b):  # column-major 4x4
        return [sum(a[k * 4 + r] * b[c * 4 + k] for k in range(4)) for c in range(4) for r in range(4)]

    def local(node):
        if 'matrix' in node:
            return [float(x) for x in node['matrix']]
        tx, ty, tz = node.get('translation', [0, 0, 0])
        qx, qy, qz, qw = node.get('rotation', [0, 0, 0, 1])
        sx, sy, sz = node.get('scale', [1, 1, 1])
        r = [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qz * qw), 2 * (qx * qz - qy * qw),
             2 * (qx * qy - qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qx * qw),
             2 * (qx * qz + qy * qw), 2 * (qy * qz - qx * qw), 1 - 2 * (qx * qx + qy * qy)]
        return [r[0] * sx, r[1] * sx, r[2] * sx, 0, r[3] * sy, r[4] * sy, r[5] * sy, 0,
                r[6] * sz, r[7] * sz, r[8] * sz, 0, tx, ty, tz, 1]

    identity = [1.0 if r == c else 0.0 for c in range(4) for r in range(4)]
    worlds = {}
    scenes = j.get('scenes', [])
    if scenes:
        stack = [(n, identity) for n in reversed(scenes[j.get('scene', 0)].get('nodes', []))]
        while stack:
            index, parent = stack.pop()
            node = j['nodes'][index]
            world = multiply(parent, local(node))
            if 'mesh' in node and node['mesh'] not in worlds:
                worlds[node['mesh']] = world
            stack += [(c, world) for c in reversed(node.get('children', []))]
    return [worlds.get(m, identity) for m in range(len(j.get('meshes', [])))]


def determinant3(m):
    a, b, c, d, e, f, g, h, i = m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def transform(m, p):
    return tuple(m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r] for r in range(3))


def atlas_groups(run, j):
    """[(report group name prefix, [(mesh, primitive), ...])] in the order the program makes them."""
    parts = rewritten(run, j)
    group = option(run, '--group', 'mesh')
    if group == 'scene':
        if option(run, '--mesh') is not None:
            return [('mesh %d' % parts[0][0], parts)]
        return [('scene', parts)]
    if group == 'primitive':
        return [('meshes[%d].primitives[%d]' % part, [part]) for part in parts]
    meshes = sorted({m for m, _ in parts})
    return [('mesh %d' % m, [part for part in parts if part[0] == m]) for m in meshes]


class GltfFiles(unittest.TestCase):
    maxDiff = 4000

    # ---------------------------------------------------------------- attributes, texcoords, indices
    def check_attributes(self, run):
        r = perform(run)
        problems = []
        chosen = selected_meshes(run, r.jin)
        overwrite = '--overwrite' in run.options
        compressed = uses_meshopt(r.jin)
        info = None
        if compressed:
            done = harmonia('info', r.input, '--json')
            self.assertEqual(done.returncode, 0, done.stderr)
            info = json.loads(done.stdout)['gltf']['meshes']
        self.assertEqual(len(r.jout.get('meshes', [])), len(r.jin.get('meshes', [])))
        for m, mesh in enumerate(r.jin.get('meshes', [])):
            for p, prim_json in enumerate(mesh['primitives']):
                where = 'meshes[%d].primitives[%d]' % (m, p)
                out_json = r.jout['meshes'][m]['primitives'][p]
                pin, pout = r.tin[m][p], r.tout[m][p]
                if pout.get('compressed'):
                    problems.append('%s: the output is still compressed' % where)
                    continue
                if not is_triangles(prim_json) or m not in chosen:
                    # Left as it was: same attributes, indices, targets and mode, decoded.
                    if pin.get('compressed'):
                        continue
                    if sorted(prim_json['attributes']) != sorted(out_json['attributes']):
                        problems.append('%s (not rewritten): attributes %s became %s' % (
                            where, sorted(prim_json['attributes']), sorted(out_json['attributes'])))
                        continue
                    for name in prim_json['attributes']:
                        if pin['attributes'][name] != pout['attributes'][name]:
                            problems.append('%s (not rewritten): %s changed' % (where, name))
                    if pin['targets'] != pout['targets']:
                        problems.append('%s (not rewritten): its morph targets changed' % where)
                    if prim_json.get('mode', 4) != out_json.get('mode', 4):
                        problems.append('%s (not rewritten): mode changed' % where)
                    if ('indices' in prim_json) != ('indices' in out_json) or (
                            'indices' in prim_json and decoded(r.jin, r.bin_in, prim_json['indices']) !=
                            decoded(r.jout, r.bin_out, out_json['indices'])):
                        problems.append('%s (not rewritten): indices changed' % where)
                    continue
                new_set = expected_set(run, prim_json)
                expected_names = set(prim_json['attributes']) | {new_set, '_CHART'}
                if sorted(out_json['attributes']) != sorted(expected_names):
                    problems.append('%s: attributes %s, expected %s' % (where, sorted(out_json['attributes']),
                                                                         sorted(expected_names)))
                if out_json.get('mode', 4) != 4:
                    problems.append('%s: mode %s, expected 4 (triangles)' % (where, out_json.get('mode')))
                if len(out_json.get('targets', [])) != len(prim_json.get('targets', [])):
                    problems.append('%s: %d morph targets, expected %d' % (where, len(out_json.get('targets', [])),
                                                                        len(prim_json.get('targets', []))))
                    continue
                out_corners = pout['corners']
                nv_out = r.jout['accessors'][out_json['attributes']['POSITION']]['count']
                # The index type: the input's, widened only when the new vertex count needs it.
                if 'indices' not in out_json:
                    problems.append('%s: the output has no indices' % where)
                else:
                    got = r.jout['accessors'][out_json['indices']]['componentType']
                    if 'indices' in prim_json:
                        want = r.jin['accessors'][prim_json['indices']]['componentType']
                        while nv_out > INDEX_LIMIT[want]:
                            want = INDEX_WIDER[want]
                        if got != want:
                            problems.append('%s: index componentType %d for %d vertices, expected %d (input %d)' % (
                                where, got, nv_out, want, r.jin['accessors'][prim_json['indices']]['componentType']))
                    elif nv_out > INDEX_LIMIT.get(got, 0):
                        problems.append('%s: index componentType %d cannot address %d vertices' % (where, got, nv_out))
                # The new set and the chart ids.
                uv_accessor = r.jout['accessors'][out_json['attributes'].get(new_set, 0)]
                if new_set in out_json['attributes'] and (uv_accessor['type'] != 'VEC2'):
                    problems.append('%s: %s is %s' % (where, new_set, uv_accessor['type']))
                if '_CHART' in out_json['attributes']:
                    chart_accessor = r.jout['accessors'][out_json['attributes']['_CHART']]
                    if (chart_accessor['type'], chart_accessor['componentType']) != ('SCALAR', FLOAT):
                        problems.append('%s: _CHART is %s of componentType %d, expected SCALAR float' % (
                            where, chart_accessor['type'], chart_accessor['componentType']))
                    charts = pout['attributes']['_CHART']
                    for k, t in enumerate(out_corners):
                        c = {charts[i][0] for i in t}
                        if len(c) != 1 or any(x != int(x) or x < 0 for x in c):
                            problems.append('%s: triangle %d has _CHART %s' % (where, k, sorted(c)))
                            break
                if new_set in out_json['attributes']:
                    uvs = pout['attributes'][new_set]
                    outside = [uv for uv in uvs if not (0.0 <= uv[0] <= 1.0 and 0.0 <= uv[1] <= 1.0)]
                    if outside:
                        problems.append('%s: %d %s values outside [0, 1], e.g. %s' % (
                            where, len(outside), new_set, outside[0]))
                if pin.get('compressed'):
                    want = info[m]['primitives'][p]['triangles']
                    if len(out_corners) != want:
                        problems.append('%s: %d triangles, `harmonia info` says the input has %d' % (
                            where, len(out_corners), want))
                    continue
                # The input's attributes (and component types) at every corner.
                names = sorted(n for n in prim_json['attributes'] if not (overwrite and n == new_set) and n != '_CHART')
                for name in names:
                    a_in = r.jin['accessors'][prim_json['attributes'][name]]
                    a_out = r.jout['accessors'][out_json['attributes'][name]]
                    for key in ('type', 'componentType'):
                        if a_in[key] != a_out[key]:
                            problems.append('%s: %s %s %s became %s' % (where, name, key, a_in[key], a_out[key]))
                    if bool(a_in.get('normalized')) != bool(a_out.get('normalized')):
                        problems.append('%s: %s normalized %s became %s' % (
                            where, name, a_in.get('normalized', False), a_out.get('normalized', False)))
                for t, (target_in, target_out) in enumerate(zip(prim_json.get('targets', []), out_json.get('targets', []))):
                    if sorted(target_in) != sorted(target_out):
                        problems.append('%s: targets[%d] holds %s, expected %s' % (where, t, sorted(target_out), sorted(target_in)))
                if problems and problems[-1].startswith(where + ': targets['):
                    continue
                in_corners = input_triangles(pin)
                if len(in_corners) != len(out_corners):
                    problems.append('%s: %d triangles, the input has %d' % (where, len(out_corners), len(in_corners)))
                    continue
                sig_in = [signature(pin, names, pin['targets'], v) for v in range(len(pin['attributes']['POSITION']))]
                sig_out = [signature(pout, names, pout['targets'], v) for v in range(len(pout['attributes']['POSITION']))]
                rotations = (0, 1, 2) if pin['mode'] in (5, 6) else (0,)
                uvs = pout['attributes'].get(new_set)
                charts = pout['attributes'].get('_CHART')
                corner_keys = set()  # (input vertex, uv, chart) at each corner
                for k, (a, b) in enumerate(zip(in_corners, out_corners)):
                    turn = next((s for s in rotations if all(sig_out[b[(c + s) % 3]] == sig_in[a[c]] for c in range(3))), None)
                    if turn is not None:
                        if uvs and charts:
                            corner_keys.update((a[c], uvs[b[(c + turn) % 3]], charts[b[(c + turn) % 3]]) for c in range(3))
                        continue
                    detail = []
                    for c in range(3):
                        for ni, name in enumerate(names):
                            if sig_out[b[c]][0][ni] != sig_in[a[c]][0][ni]:
                                detail.append('corner %d %s: input vertex %d %s, output vertex %d %s' % (
                                    c, name, a[c], sig_in[a[c]][0][ni], b[c], sig_out[b[c]][0][ni]))
                        if sig_out[b[c]][1] != sig_in[a[c]][1]:
                            detail.append('corner %d: morph target deltas differ (input vertex %d, output vertex %d)' % (
                                c, a[c], b[c]))
                    problems.append('%s: triangle %d differs from the input%s: %s' % (
                        where, k, ' (up to rotation)' if len(rotations) > 1 else '', '; '.join(detail[:4])))
                    break
                else:
                    # Split only where the atlas needs it: one output vertex per distinct (input
                    # vertex, atlas uv, chart) at the corners, and none that no triangle uses.
                    used = {i for t in out_corners for i in t}
                    if corner_keys and (len(used) != nv_out or nv_out != len(corner_keys)):
                        problems.append('%s: %d output vertices (%d used by triangles) for %d distinct '
                                        '(input vertex, uv, chart) corners' % (where, nv_out, len(used), len(corner_keys)))
        self.assertEqual(problems, [], '\n' + '\n'.join(problems[:20]))

    # ---------------------------------------------------------------- the rest of the document
    def check_document(self, run):
        r = perform(run)
        compressed = uses_meshopt(r.jin)
        problems = []
        before = document_view(r.jin, r.bin_in, os.path.dirname(os.path.abspath(r.input)), compressed)
        after = document_view(r.jout, r.bin_out, os.path.dirname(os.path.abspath(r.output)), compressed)
        for key in sorted(set(before) | set(after)):
            if before.get(key) != after.get(key):
                problems.append('%s differs: input %s, output %s' % (
                    key, json.dumps(before.get(key))[:600], json.dumps(after.get(key))[:600]))
        for key in ('extensionsUsed', 'extensionsRequired'):  # the same, less meshopt once decoded
            want = [e for e in r.jin.get(key, []) if not (compressed and e == 'EXT_meshopt_compression')]
            if r.jout.get(key, []) != want:
                problems.append('%s: %s, expected %s (input %s)' % (key, r.jout.get(key), want, r.jin.get(key)))
        if uses_meshopt(r.jout):
            problems.append('the output still holds EXT_meshopt_compression buffer views')
        for m, mesh in enumerate(r.jin.get('meshes', [])):
            out_mesh = r.jout['meshes'][m]
            strip = lambda x: {k: v for k, v in x.items() if k != 'primitives'}  # noqa: E731
            if strip(mesh) != strip(out_mesh):
                problems.append('meshes[%d] (outside its primitives) differs: %s against %s' % (m, strip(out_mesh), strip(mesh)))
            if len(mesh['primitives']) != len(out_mesh['primitives']):
                problems.append('meshes[%d] has %d primitives, input %d' % (m, len(out_mesh['primitives']), len(mesh['primitives'])))
                continue
            for p, (a, b) in enumerate(zip(mesh['primitives'], out_mesh['primitives'])):
                keep = lambda x: {k: v for k, v in x.items() if k not in ('attributes', 'indices', 'targets', 'mode')}  # noqa: E731
                if keep(a) != keep(b):
                    problems.append('meshes[%d].primitives[%d] outside attributes/indices/targets/mode: %s against %s' % (
                        m, p, keep(b), keep(a)))
        # One buffer, and nothing left over: the accessors and views nobody refers to are the
        # input's unused ones.
        buffers = r.jout.get('buffers', [])
        if len(buffers) != 1:
            problems.append('%d buffers, expected 1' % len(buffers))
        elif run.suffix == '.glb':
            if 'uri' in buffers[0]:
                problems.append('the GLB buffer has a uri: %s' % buffers[0]['uri'][:80])
        else:
            # OUT.bin beside OUT.gltf, named by a relative URI reference (RFC 3986: what a path
            # may hold, anything else percent-encoded).
            uri, name = buffers[0].get('uri', ''), run.stem + '.bin'
            if (urllib.parse.unquote(uri) != name or not URI_PATH.fullmatch(uri) or
                    not os.path.isfile(os.path.join(os.path.dirname(r.output), name))):
                problems.append('the .gltf buffer has uri %r: expected %r (%s beside the .gltf, percent-encoded)' % (
                    uri[:80], urllib.parse.quote(name, safe="!$&'()*+,;=@"), name))
        (ain, vin), (aout, vout) = references(r.jin), references(r.jout)
        unused_in = len(r.jin.get('accessors', [])) - len(ain)
        unused_out = len(r.jout.get('accessors', [])) - len(aout)
        if unused_in != unused_out:
            problems.append('%d accessors nothing refers to (input: %d)' % (unused_out, unused_in))
        unused_in = len(r.jin.get('bufferViews', [])) - len(vin)
        unused_out = len(r.jout.get('bufferViews', [])) - len(vout)
        if unused_in != unused_out:
            problems.append('%d buffer views nothing refers to (input: %d)' % (unused_out, unused_in))
        self.assertEqual(problems, [], '\n' + '\n'.join(problems))

    # ---------------------------------------------------------------- the atlas, by atlaseval.py
    def check_atlas(self, run):
        r = perform(run)
        worlds = world_matrices(r.jout)
        resolution = int(option(run, '--resolution', 1024))
        reports = r.report.get('atlases', [])
        problems = []
        groups = atlas_groups(run, r.jout)
        if r.report.get('primitives_written') != len(rewritten(run, r.jout)):
            problems.append('the report says %s primitives written, expected %d' % (
                r.report.get('primitives_written'), len(rewritten(run, r.jout))))
        if len(groups) != len(reports):
            problems.append('%d atlases reported, %d expected' % (len(reports), len(groups)))
        for g, (label, parts) in enumerate(groups):
            lines_v, lines_vt, lines_f = [], [], []
            base = 0
            faces, charts = 0, set()
            last_chart = None
            for m, p in parts:
                new_set = expected_set(run, r.jin['meshes'][m]['primitives'][p])
                pout = r.tout[m][p]
                if pout.get('compressed') or new_set not in pout['attributes'] or '_CHART' not in pout['attributes']:
                    problems.append('%s: meshes[%d].primitives[%d] has no %s/_CHART to judge' % (label, m, p, new_set))
                    continue
                world = worlds[m]
                mirrored = determinant3(world) < 0
                for position in pout['attributes']['POSITION']:
                    lines_v.append('v %.9g %.9g %.9g' % transform(world, position))
                for u, v in pout['attributes'][new_set]:
                    lines_vt.append('vt %.9g %.9g' % (u, 1.0 - v))
                chart_of = pout['attributes']['_CHART']
                for a, b, c in pout['corners']:
                    chart = int(chart_of[a][0])
                    charts.add(chart)
                    if chart != last_chart:
                        lines_f.append('g chart_%d' % chart)
                        last_chart = chart
                    if mirrored:
                        b, c = c, b
                    lines_f.append('f %d/%d %d/%d %d/%d' % (a + base + 1, a + base + 1, b + base + 1, b + base + 1,
                                                          c + base + 1, c + base + 1))
                    faces += 1
                base += len(pout['attributes']['POSITION'])
            if not lines_f:
                continue
            obj = Scratch.path('out-' + run.name, 'atlas%d.obj' % g)
            with open(obj, 'w') as out:
                out.write('\n'.join(lines_v + lines_vt + lines_f) + '\n')
            try:
                evaluation = atlaseval.evaluate(obj, obj, (resolution, resolution))
            except SystemExit:
                problems.append('%s: atlaseval refused %s' % (label, obj))
                continue
            figures = {k: evaluation[k] for k in ('flipped', 'zero_area_uv', 'mirrored_charts', 'overlap_texels',
                                                  'unassigned_faces', 'tris_outside_atlas', 'nonmanifold_uv_edges')}
            figures['boundary_crossings'] = evaluation['boundary_crossings']
            bad = (not evaluation['valid'] or evaluation['mirrored_charts'] or evaluation['tris_outside_atlas'])
            if bad:
                problems.append('%s: atlaseval: %s (%s)' % (label, json.dumps(figures), obj))
            report = next((x for x in reports if x.get('group', '') == label or
                           x.get('group', '').startswith(label + ' ')), None)
            if report is None:
                problems.append('%s: no atlas of that name in the report (%s)' % (label, [x.get('group') for x in reports]))
                continue
            if report.get('faces') != faces or report.get('charts') != len(charts):
                problems.append('%s: the report says %s faces in %s charts; the file has %d in %d' % (
                    label, report.get('faces'), report.get('charts'), faces, len(charts)))
            for key in ('flipped_triangles', 'overlapping_texels', 'boundary_crossings', 'dropped_faces'):
                if report.get(key):
                    problems.append('%s: the report says %s %s' % (label, key, report.get(key)))
        self.assertEqual(problems, [], '\n' + '\n'.join(problems))

    # ---------------------------------------------------------------- the Khronos validator
    def check_validator(self, run):
        r = perform(run)
        found = validate([r.input, r.output])
        before, after = found[r.input], found[r.output]
        errors = [m for m in after if m['severity'] == 0]
        warnings_in = {m['code'] for m in before if m['severity'] == 1}
        new_warnings = [m for m in after if m['severity'] == 1 and m['code'] not in warnings_in]
        self.assertEqual((errors[:10], new_warnings[:10]), ([], []),
                         'errors and new warnings of the validator on %s' % r.output)


VALIDATOR_SCRIPT = r"""
const fs = require('fs'), path = require('path');
const validator = require('gltf-validator');
(async () => {
  for (const file of process.argv.slice(2)) {
    const dir = path.dirname(file);
    let messages;
    try {
      const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
        uri: path.basename(file), maxIssues: 0,
        externalResourceFunction: (uri) => new Promise((ok, bad) => {
          try { ok(new Uint8Array(fs.readFileSync(path.join(dir, decodeURIComponent(uri))))); }
          catch (e) { bad(e.toString()); }
        }),
      });
      messages = report.issues.messages.map(m => ({code: m.code, severity: m.severity, pointer: m.pointer || '',
                                                  message: m.message}));
    } catch (e) {
      messages = [{code: 'EXCEPTION', severity: 0, pointer: '', message: String(e)}];
    }
    console.log(JSON.stringify({file, messages}));
  }
})();
"""

_validated = {}


def validate(paths):
    """The validator's messages for each file: all runs' files in one node process, the first time."""
    todo = [p for p in paths if p not in _validated]
    if todo:
        node = shutil.which('node')
        if node is None:
            missing('node is not installed (.ci/install-deps installs it)')
        if not os.path.isfile(os.path.join(NODE_PATH, 'gltf-validator', 'package.json')):
            missing('gltf-validator is not installed in %s (HARMONIA_NODE_PATH; .ci/install-deps puts it there)' % NODE_PATH)
        batch = set(todo)
        for run in RUNS:  # the other runs' files too: one start of node for all
            if isinstance(run.result, Result):
                batch.update((run.result.input, run.result.output))
        batch -= set(_validated)
        script = Scratch.path('validate.js')
        with open(script, 'w') as out:
            out.write(VALIDATOR_SCRIPT)
        env = dict(os.environ, NODE_PATH=NODE_PATH)
        done = subprocess.run([node, script] + sorted(batch), capture_output=True, text=True, env=env, timeout=600)
        if done.returncode != 0:
            raise AssertionError('the validator failed: %s' % done.stderr[-2000:])
        for line in done.stdout.splitlines():
            record = json.loads(line)
            _validated[record['file']] = record['messages']
    return {p: _validated[p] for p in paths}


def add_tests():
    for run in RUNS:
        for check in ('attributes', 'document', 'validator', 'atlas'):
            def test(self, run=run, check=check):
                getattr(self, 'check_' + check)(run)
            test.__name__ = 'test_%s__%s' % (run.name, check)
            test.__doc__ = '%s %s: %s' % (run.source, ' '.join(run.options + ['->', run.stem + run.suffix]), check)
            setattr(GltfFiles, test.__name__, test)


add_tests()


class Refusals(unittest.TestCase):
    """What the program must refuse, naming the place, and without writing anything."""

    def refused(self, source, options, *needles):
        need_tools()
        source = source_path(source)
        folder = Scratch.path('refused-%d' % len(os.listdir(Scratch.path())))
        os.makedirs(folder)
        output = os.path.join(folder, 'out.glb')
        done = harmonia('atlas', source, output, *options)
        self.assertNotEqual(done.returncode, 0, 'harmonia atlas %s %s accepted it' % (source, ' '.join(options)))
        message = done.stderr + done.stdout
        for needle in needles:
            self.assertIn(needle, message)
        self.assertEqual(os.listdir(folder), [], 'a refused run left files behind')
        return message

    def test_texcoord_0_on_a_textured_primitive_needs_overwrite(self):
        self.refused('Duck.glb', ['--texcoord', '0'], 'meshes[0].primitives[0]', 'TEXCOORD_0')

    def test_texcoord_with_a_gap_is_refused(self):
        self.refused('Duck.glb', ['--texcoord', '5'], 'meshes[0].primitives[0]')

    def test_texcoord_1_on_a_bare_primitive_is_a_gap(self):
        self.refused('gen:normalized_uv', ['--texcoord', '1'], 'meshes[0].primitives[2]')

    def test_accessor_beyond_its_buffer_view(self):
        self.refused('gen:overrun', [], 'meshes[0].primitives[0].attributes.POSITION', 'accessor')

    def test_output_bin_is_not_the_input_buffer(self):
        """IN.gltf's buffer is OUT.bin, in the folder OUT.gltf goes to: writing OUT.bin there would
        destroy the input. Refused, or written elsewhere; either way the input stays whole."""
        need_tools()
        folder = Scratch.path('clobber')
        os.makedirs(folder)
        source = gen_external(folder)
        with open(source) as text:
            document = json.load(text)
        os.rename(os.path.join(folder, 'external.bin'), os.path.join(folder, 'out.bin'))
        document['buffers'][0]['uri'] = 'out.bin'
        with open(source, 'w') as out:
            json.dump(document, out)
        def contents(name):
            with open(os.path.join(folder, name), 'rb') as data:
                return data.read()
        before = {name: contents(name) for name in os.listdir(folder)}
        done = harmonia('atlas', source, os.path.join(folder, 'out.gltf'))
        after = {name: contents(name) for name in before}
        changed = sorted(name for name in before if before[name] != after[name])
        self.assertEqual(changed, [], 'harmonia atlas external.gltf out.gltf (exit %d) overwrote the input\'s %s' % (
            done.returncode, ', '.join(changed)))

    def test_generated_inputs_are_valid(self):
        """The test's own writer: every generated input passes the validator without errors."""
        need_tools()
        paths = [source_path('gen:' + key) for key in GENERATORS if key != 'overrun']
        found = validate(paths)
        problems = {os.path.basename(p): [m for m in found[p] if m['severity'] <= 1][:5] for p in paths}
        self.assertEqual({k: v for k, v in problems.items() if v}, {})


def main():
    program = unittest.main(exit=False, verbosity=2 if '-v' in sys.argv else 1)
    result = program.result
    if not result.wasSuccessful():
        return 1
    return 77 if result.testsRun and len(result.skipped) == result.testsRun else 0


if __name__ == '__main__':
    sys.exit(main())
