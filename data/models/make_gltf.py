#!/usr/bin/env python3
"""Writes data/models/teapot.gltf from data/models/teapot.ply (data/models/NOTICE.md).

The glTF holds exactly the PLY's float32 positions and triangles in one embedded base64
buffer (uint16 indices), under a two-node hierarchy (a parent scaling the model units to
metres, a child translated by (1, 0, 0) model units) so loaders must compose node
transforms, and one metallic-roughness material with a 2x2 sRGB base-colour texture (an
embedded PNG) so the texture mean is exercised.
   python3 data/models/make_gltf.py
"""
import base64, json, os, struct, zlib

here = os.path.dirname(os.path.abspath(__file__))


def read_ply(path):
    data = open(path, 'rb').read()
    end = data.index(b'end_header\n') + len(b'end_header\n')
    header = data[:end].decode('ascii').splitlines()
    nv = nf = 0
    face_count_type, face_index_type = 'B', 'i'
    types = {'uchar': 'B', 'uint8': 'B', 'int': 'i', 'int32': 'i', 'uint': 'I', 'uint32': 'I'}
    for line in header:
        w = line.split()
        if w[:2] == ['element', 'vertex']: nv = int(w[2])
        if w[:2] == ['element', 'face']: nf = int(w[2])
        if w[:2] == ['property', 'list']:
            face_count_type, face_index_type = types[w[2]], types[w[3]]
    assert 'format binary_little_endian 1.0' in header
    at = end
    positions = list(struct.unpack_from('<%df' % (3 * nv), data, at))
    at += 12 * nv
    tris = []
    for _ in range(nf):
        (n,) = struct.unpack_from('<' + face_count_type, data, at)
        at += struct.calcsize(face_count_type)
        idx = struct.unpack_from('<%d%s' % (n, face_index_type), data, at)
        at += n * struct.calcsize(face_index_type)
        for k in range(1, n - 1):  # fan (the teapot's faces are triangles already)
            tris += [idx[0], idx[k], idx[k + 1]]
    return positions, tris


def png(width, height, rows):
    def chunk(kind, body):
        return struct.pack('>I', len(body)) + kind + body + struct.pack('>I', zlib.crc32(kind + body))
    raw = b''.join(b'\x00' + bytes(r) for r in rows)
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, 2, 0, 0, 0))
            + chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))


positions, tris = read_ply(os.path.join(here, 'teapot.ply'))
nv = len(positions) // 3
assert nv < 65536
pos_bytes = struct.pack('<%df' % len(positions), *positions)
idx_bytes = struct.pack('<%dH' % len(tris), *tris)
idx_bytes += b'\x00' * (-len(idx_bytes) % 4)
buf = pos_bytes + idx_bytes
mins = [min(positions[i::3]) for i in range(3)]
maxs = [max(positions[i::3]) for i in range(3)]
texture = png(2, 2, [[255, 255, 255, 188, 188, 188], [255, 255, 255, 188, 188, 188]])
doc = {
    'asset': {'version': '2.0', 'generator': 'penumbra data/models/make_gltf.py',
              'copyright': 'Utah teapot (Martin Newell, 1975), public domain; see NOTICE.md'},
    'scene': 0,
    'scenes': [{'nodes': [0]}],
    'nodes': [{'name': 'metres', 'scale': [0.016, 0.016, 0.016], 'children': [1]},
              {'name': 'teapot', 'mesh': 0, 'translation': [1.0, 0.0, 0.0]}],
    'meshes': [{'name': 'teapot', 'primitives': [
        {'attributes': {'POSITION': 0}, 'indices': 1, 'material': 0, 'mode': 4}]}],
    'materials': [{'name': 'glazed blue', 'pbrMetallicRoughness': {
        'baseColorFactor': [0.30, 0.42, 0.62, 1.0], 'metallicFactor': 0.0,
        'roughnessFactor': 0.35, 'baseColorTexture': {'index': 0}}}],
    'textures': [{'source': 0}],
    'images': [{'uri': 'data:image/png;base64,' + base64.b64encode(texture).decode('ascii')}],
    'accessors': [
        {'bufferView': 0, 'componentType': 5126, 'count': nv, 'type': 'VEC3', 'min': mins, 'max': maxs},
        {'bufferView': 1, 'componentType': 5123, 'count': len(tris), 'type': 'SCALAR'}],
    'bufferViews': [
        {'buffer': 0, 'byteOffset': 0, 'byteLength': len(pos_bytes), 'target': 34962},
        {'buffer': 0, 'byteOffset': len(pos_bytes), 'byteLength': 2 * len(tris), 'target': 34963}],
    'buffers': [{'byteLength': len(buf),
                 'uri': 'data:application/octet-stream;base64,' + base64.b64encode(buf).decode('ascii')}],
}
with open(os.path.join(here, 'teapot.gltf'), 'w') as f:
    json.dump(doc, f, indent=1)
    f.write('\n')
print('teapot.gltf: %d vertices, %d triangles' % (nv, len(tris) // 3))
