"""Point cloud files with numpy only: PLY (ascii, binary little/big endian), PCD (ascii, binary)
and NPZ, read into a structured array and written back in the same format with fields added.

`read_cloud(path)` returns a CloudFile: `points`, a structured array of the file's per-point
fields (PLY's vertex element, PCD's fields, an NPZ's arrays), and what is needed to write the
file again in its own format and layout (`write_cloud(path, cloud_file, points)`). Only what
point cloud tools commonly write is supported; anything else (PLY list properties in the vertex
element, PCD binary_compressed) is refused with a ValueError that says so.
"""
import os
import re
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

FORMATS = ('ply', 'pcd', 'npz')

_PLY_TYPES = {
    'char': 'i1', 'int8': 'i1', 'uchar': 'u1', 'uint8': 'u1', 'short': 'i2', 'int16': 'i2',
    'ushort': 'u2', 'uint16': 'u2', 'int': 'i4', 'int32': 'i4', 'uint': 'u4', 'uint32': 'u4',
    'float': 'f4', 'float32': 'f4', 'double': 'f8', 'float64': 'f8',
}
_PLY_NAMES = {'i1': 'char', 'u1': 'uchar', 'i2': 'short', 'u2': 'ushort', 'i4': 'int', 'u4': 'uint',
              'f4': 'float', 'f8': 'double'}
_PLY_ENDIAN = {'ascii': '<', 'binary_little_endian': '<', 'binary_big_endian': '>'}


@dataclass
class CloudFile:
    path: str
    format: str                 # 'ply', 'pcd' or 'npz'
    encoding: str               # ply: ascii / binary_little_endian / binary_big_endian; pcd: ascii / binary; npz: ''
    points: np.ndarray          # structured, one entry per point
    header: List[str] = field(default_factory=list)   # ply: comments, then the other elements' lines
    trailer: bytes = b''        # ply: the data of the elements after the vertex element, verbatim
    pcd_names: List[str] = field(default_factory=list)  # pcd: the FIELDS as written ('_' repeats)
    pcd_header: Dict[str, str] = field(default_factory=dict)  # pcd: VERSION, VIEWPOINT, WIDTH, HEIGHT
    arrays: Dict[str, np.ndarray] = field(default_factory=dict)  # npz: every array of the file


def format_of(path) -> Optional[str]:
    ext = os.path.splitext(str(path))[1].lower().lstrip('.')
    return ext if ext in FORMATS else None


def read_cloud(path) -> CloudFile:
    fmt = format_of(path)
    if fmt == 'ply':
        return _read_ply(str(path))
    if fmt == 'pcd':
        return _read_pcd(str(path))
    if fmt == 'npz':
        return _read_npz(str(path))
    raise ValueError('%s: unknown format (expected a .ply, .pcd or .npz file)' % path)


def write_cloud(path, source: CloudFile, points: np.ndarray, extra_arrays=None):
    """Writes `points` (the source's fields plus new ones) in the source's format and encoding.
    For NPZ, `extra_arrays` are stored beside the source's arrays."""
    path = str(path)
    if source.format == 'ply':
        _write_ply(path, source, points)
    elif source.format == 'pcd':
        _write_pcd(path, source, points)
    else:
        arrays = dict(source.arrays)
        arrays.update(extra_arrays or {})
        np.savez(path, **arrays)


def _read_header(f, end_marker, path, limit=1000):
    lines = []
    while True:
        line = f.readline()
        if not line:
            raise ValueError('%s: the header ends before %r' % (path, end_marker))
        text = line.decode('ascii', 'replace').strip()
        lines.append(text)
        if text.split()[:1] == [end_marker] or (end_marker == 'DATA' and text.startswith('DATA')):
            return lines
        if len(lines) > limit:
            raise ValueError('%s: no %r within %d header lines' % (path, end_marker, limit))


# --- PLY --------------------------------------------------------------------------------------------

def _read_ply(path):
    with open(path, 'rb') as f:
        if f.readline().strip() != b'ply':
            raise ValueError('%s: not a PLY file (no "ply" on the first line)' % path)
        lines = _read_header(f, 'end_header', path)
        body = f.read()
    encoding, elements, comments = None, [], []
    for line in lines[:-1]:
        words = line.split()
        if not words:
            continue
        if words[0] == 'format':
            encoding = words[1] if len(words) > 1 else ''
            if encoding not in _PLY_ENDIAN:
                raise ValueError('%s: PLY format %r is not supported (ascii, binary_little_endian, '
                                 'binary_big_endian)' % (path, encoding))
        elif words[0] == 'element':
            elements.append({'name': words[1], 'count': int(words[2]), 'props': [], 'lists': False,
                             'lines': [line]})
        elif words[0] == 'property':
            if not elements:
                raise ValueError('%s: a property before any element' % path)
            elements[-1]['lines'].append(line)
            if words[1] == 'list':
                elements[-1]['lists'] = True
            elif words[1] not in _PLY_TYPES:
                raise ValueError('%s: unknown PLY property type %r' % (path, words[1]))
            else:
                elements[-1]['props'].append((words[2], _PLY_TYPES[words[1]]))
        elif words[0] in ('comment', 'obj_info'):
            comments.append(line)
    if encoding is None:
        raise ValueError('%s: the PLY header has no format line' % path)
    if not elements or elements[0]['name'] != 'vertex':
        raise ValueError('%s: the vertex element must come first in the PLY file' % path)
    vertex = elements[0]
    if vertex['lists']:
        raise ValueError('%s: list properties in the vertex element are not supported' % path)
    endian = _PLY_ENDIAN[encoding]
    dtype = np.dtype([(name, endian + t) for name, t in vertex['props']])
    n = vertex['count']
    if encoding == 'ascii':
        text = body.decode('ascii', 'replace').split('\n')
        rows = text[:n]
        if len(rows) < n:
            raise ValueError('%s: %d vertices declared, %d lines found' % (path, n, len(rows)))
        values = np.array(' '.join(rows).split(), dtype=np.float64) if n else np.zeros(0)
        if values.size != n * len(dtype.names):
            raise ValueError('%s: expected %d values on each vertex line' % (path, len(dtype.names)))
        values = values.reshape(n, len(dtype.names))
        points = np.empty(n, dtype)
        for k, name in enumerate(dtype.names):
            points[name] = values[:, k]
        trailer = '\n'.join(text[n:]).encode('ascii')
    else:
        if len(body) < n * dtype.itemsize:
            raise ValueError('%s: the file is shorter than its %d vertices' % (path, n))
        points = np.frombuffer(body, dtype, count=n).copy()
        trailer = body[n * dtype.itemsize:]
    # Elements after the vertices (faces of a mesh, ...) are written back verbatim.
    after = [line for e in elements[1:] for line in e['lines']]
    return CloudFile(path, 'ply', encoding, points, header=comments + ['\0after'] + after, trailer=trailer)


def _write_ply(path, source, points):
    split = source.header.index('\0after')
    comments, after = source.header[:split], source.header[split + 1:]
    endian = _PLY_ENDIAN[source.encoding]
    lines = ['ply', 'format %s 1.0' % source.encoding] + comments
    lines.append('element vertex %d' % len(points))
    for name in points.dtype.names:
        t = points.dtype[name]
        lines.append('property %s %s' % (_PLY_NAMES[t.kind + str(t.itemsize)], name))
    lines += after + ['end_header']
    with open(path, 'wb') as f:
        f.write(('\n'.join(lines) + '\n').encode('ascii'))
        if source.encoding == 'ascii':
            _write_ascii_rows(f, points)
        else:
            out = points.astype(np.dtype([(n, endian + points.dtype[n].kind + str(points.dtype[n].itemsize))
                                          for n in points.dtype.names]))
            f.write(out.tobytes())
        f.write(source.trailer)


def _write_ascii_rows(f, points, columns=None):
    """One line per point; floats with enough digits to read back the same float32/float64."""
    columns = columns or [points[n] for n in points.dtype.names]
    formats = []
    flat = []
    for c in columns:
        c = c.reshape(len(points), -1)
        for k in range(c.shape[1]):
            flat.append(c[:, k])
            formats.append('%.9g' if c.dtype.kind == 'f' and c.dtype.itemsize == 4 else
                           '%.17g' if c.dtype.kind == 'f' else '%d')
    if len(points):
        fmt = ' '.join(formats)
        rows = zip(*[column.tolist() for column in flat])
        f.write(('\n'.join(fmt % row for row in rows) + '\n').encode('ascii'))


# --- PCD --------------------------------------------------------------------------------------------

def _read_pcd(path):
    with open(path, 'rb') as f:
        lines = _read_header(f, 'DATA', path)
        body = f.read()
    header = {}
    for line in lines:
        if not line or line.startswith('#'):
            continue
        key, _, value = line.partition(' ')
        header[key.upper()] = value.strip()
    for key in ('FIELDS', 'SIZE', 'TYPE', 'DATA'):
        if key not in header:
            raise ValueError('%s: the PCD header has no %s line' % (path, key))
    names = header['FIELDS'].split()
    sizes = [int(s) for s in header['SIZE'].split()]
    types = header['TYPE'].split()
    counts = [int(c) for c in header.get('COUNT', ' '.join(['1'] * len(names))).split()]
    if not (len(names) == len(sizes) == len(types) == len(counts)):
        raise ValueError('%s: FIELDS, SIZE, TYPE and COUNT differ in length' % path)
    width = int(header.get('WIDTH', '0'))
    height = int(header.get('HEIGHT', '1'))
    n = int(header.get('POINTS', str(width * height)))
    encoding = header['DATA'].split()[0]
    if encoding not in ('ascii', 'binary'):
        raise ValueError('%s: PCD DATA %s is not supported (ascii, binary)' % (path, encoding))
    # Repeated names ('_' padding of PCL) get unique names inside the array.
    unique, seen = [], {}
    for name in names:
        seen[name] = seen.get(name, 0) + 1
        unique.append(name if names.count(name) == 1 else '%s%d' % (name, seen[name]))
    kinds = {'F': 'f', 'I': 'i', 'U': 'u'}
    fields = []
    for name, size, kind, count in zip(unique, sizes, types, counts):
        if kind not in kinds:
            raise ValueError('%s: unknown PCD TYPE %r' % (path, kind))
        t = '<%s%d' % (kinds[kind], size)
        fields.append((name, t) if count == 1 else (name, t, (count,)))
    dtype = np.dtype(fields)
    if encoding == 'binary':
        if len(body) < n * dtype.itemsize:
            raise ValueError('%s: the file is shorter than its %d points' % (path, n))
        points = np.frombuffer(body, dtype, count=n).copy()
    else:
        rows = [r for r in body.decode('ascii', 'replace').split('\n') if r.strip()][:n]
        if len(rows) < n:
            raise ValueError('%s: %d points declared, %d lines found' % (path, n, len(rows)))
        columns = sum(counts)
        tokens = ' '.join(rows).split()
        if len(tokens) != n * columns:
            raise ValueError('%s: expected %d values per point line' % (path, columns))
        values = np.array(tokens, np.float64).reshape(n, columns) if n else np.zeros((0, columns))
        points = np.empty(n, dtype)
        k = 0
        for name, count in zip(unique, counts):
            points[name] = values[:, k] if count == 1 else values[:, k:k + count]
            k += count
    return CloudFile(path, 'pcd', encoding, points, pcd_names=names,
                     pcd_header={k: header[k] for k in ('VERSION', 'VIEWPOINT', 'WIDTH', 'HEIGHT') if k in header})


def _write_pcd(path, source, points):
    n = len(points)
    added = [name for name in points.dtype.names if name not in source.points.dtype.names]
    names = list(source.pcd_names) + added
    sizes, types, counts = [], [], []
    for name in points.dtype.names:
        t = points.dtype[name]
        base = t.base if t.subdtype else t
        sizes.append(str(base.itemsize))
        types.append({'f': 'F', 'i': 'I', 'u': 'U'}[base.kind])
        counts.append(str(int(np.prod(t.shape)) if t.subdtype else 1))
    organised = source.pcd_header.get('HEIGHT', '1') != '1' and n == len(source.points)
    width = source.pcd_header.get('WIDTH', str(n)) if organised else str(n)
    height = source.pcd_header.get('HEIGHT', '1') if organised else '1'
    lines = ['# .PCD v0.7 - Point Cloud Data file format (labelled by ohm_mirror_detector3d)',
             'VERSION %s' % source.pcd_header.get('VERSION', '0.7'),
             'FIELDS ' + ' '.join(names), 'SIZE ' + ' '.join(sizes), 'TYPE ' + ' '.join(types),
             'COUNT ' + ' '.join(counts), 'WIDTH ' + width, 'HEIGHT ' + height,
             'VIEWPOINT ' + source.pcd_header.get('VIEWPOINT', '0 0 0 1 0 0 0'), 'POINTS %d' % n,
             'DATA ' + source.encoding]
    with open(path, 'wb') as f:
        f.write(('\n'.join(lines) + '\n').encode('ascii'))
        if source.encoding == 'binary':
            f.write(points.astype(points.dtype.newbyteorder('<')).tobytes())
        else:
            _write_ascii_rows(f, points)


# --- NPZ --------------------------------------------------------------------------------------------

def _read_npz(path):
    with np.load(path, allow_pickle=False) as data:
        arrays = {k: data[k] for k in data.files}
    return CloudFile(path, 'npz', '', np.zeros(0), arrays=arrays)


def structured(columns: Dict[str, np.ndarray]) -> np.ndarray:
    """A structured array of equally long columns, in the given order."""
    items = list(columns.items())
    n = len(items[0][1]) if items else 0
    out = np.empty(n, [(k, np.asarray(v).dtype, np.asarray(v).shape[1:]) for k, v in items])
    for k, v in items:
        out[k] = v
    return out


def append_field(points: np.ndarray, name: str, values: np.ndarray) -> np.ndarray:
    """points with one more field (a copy); replaces a field of that name."""
    columns = {n: points[n] for n in points.dtype.names if n != name}
    columns[name] = values
    return structured(columns)


def write_new(path, points: np.ndarray, encoding=None):
    """Writes a structured array as a new file of the format of `path`'s extension: PLY/PCD
    ascii or binary (default binary_little_endian / binary); NPZ: one array per field."""
    fmt = format_of(path)
    if fmt is None:
        raise ValueError('%s: unknown format (expected a .ply, .pcd or .npz file)' % path)
    if fmt == 'npz':
        np.savez(str(path), **{n: points[n] for n in points.dtype.names})
        return
    encoding = encoding or ('binary_little_endian' if fmt == 'ply' else 'binary')
    source = CloudFile(str(path), fmt, encoding, points[:0], header=['\0after'], pcd_names=list(points.dtype.names))
    write_cloud(path, source, points)
