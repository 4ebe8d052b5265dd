"""Minimal glb reading: accessors, node world matrices, skinned rest positions."""
import json, struct, math

COMP = {5120: ('b', 1), 5121: ('B', 1), 5122: ('h', 2), 5123: ('H', 2), 5125: ('I', 4), 5126: ('f', 4)}
NCOMP = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3, 'VEC4': 4, 'MAT4': 16}
NORM = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0}


def read_glb(path):
    b = open(path, 'rb').read()
    assert b[:4] == b'glTF'
    off = 12
    js, binary = None, None
    while off < len(b):
        n, kind = struct.unpack_from('<II', b, off)
        chunk = b[off + 8: off + 8 + n]
        if kind == 0x4E4F534A:
            js = json.loads(chunk)
        elif kind == 0x004E4942:
            binary = chunk
        off += 8 + n
    return js, binary


def accessor(js, binary, i):
    a = js['accessors'][i]
    assert 'sparse' not in a
    fmt, size = COMP[a['componentType']]
    k = NCOMP[a['type']]
    bv = js['bufferViews'][a['bufferView']]
    start = bv.get('byteOffset', 0) + a.get('byteOffset', 0)
    stride = bv.get('byteStride', size * k)
    out = []
    for e in range(a['count']):
        v = struct.unpack_from('<' + fmt * k, binary, start + e * stride)
        if a.get('normalized') and a['componentType'] in NORM:
            v = tuple(max(x / NORM[a['componentType']], -1.0) for x in v)
        out.append(v)
    return out


def mat_mul(a, b):
    # 4x4, column-major flat lists as glTF
    r = [0.0] * 16
    for c in range(4):
        for rr in range(4):
            r[c * 4 + rr] = sum(a[k * 4 + rr] * b[c * 4 + k] for k in range(4))
    return r


def trs(node):
    if 'matrix' in node:
        return list(node['matrix'])
    tx, ty, tz = node.get('translation', (0, 0, 0))
    x, y, z, w = node.get('rotation', (0, 0, 0, 1))
    sx, sy, sz = node.get('scale', (1, 1, 1))
    r = [1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),
         2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
         2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)]
    return [r[0] * sx, r[1] * sx, r[2] * sx, 0, r[3] * sy, r[4] * sy, r[5] * sy, 0,
            r[6] * sz, r[7] * sz, r[8] * sz, 0, tx, ty, tz, 1]


def parents(js):
    """Each node's parent node."""
    parent = {}
    for i, n in enumerate(js['nodes']):
        for c in n.get('children', []):
            parent[c] = i
    return parent


def world_matrices(js):
    nodes = js['nodes']
    parent = parents(js)
    world = {}

    def w(i):
        if i not in world:
            m = trs(nodes[i])
            world[i] = mat_mul(w(parent[i]), m) if i in parent else m
        return world[i]
    for i in range(len(nodes)):
        w(i)
    return world


def apply(m, p):
    x, y, z = p
    return (m[0] * x + m[4] * y + m[8] * z + m[12],
            m[1] * x + m[5] * y + m[9] * z + m[13],
            m[2] * x + m[6] * y + m[10] * z + m[14])


def rest_meshes(js, binary):
    """Per mesh node, per primitive: (positions at rest, triangles)."""
    world = world_matrices(js)
    scene = js.get('scenes', [{}])[js.get('scene', 0)] if js.get('scenes') else None
    in_scene = set()
    if scene:
        stack = list(scene.get('nodes', []))
        while stack:
            i = stack.pop()
            in_scene.add(i)
            stack.extend(js['nodes'][i].get('children', []))
    out = []
    for i, n in enumerate(js['nodes']):
        if 'mesh' not in n or (scene and i not in in_scene):
            continue
        skin = js['skins'][n['skin']] if 'skin' in n else None
        if skin:
            ibm = accessor(js, binary, skin['inverseBindMatrices']) if 'inverseBindMatrices' in skin else [
                (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1)] * len(skin['joints'])
            jm = [mat_mul(world[j], list(ibm[k])) for k, j in enumerate(skin['joints'])]
        for prim in js['meshes'][n['mesh']]['primitives']:
            if prim.get('mode', 4) != 4:
                continue
            pos = accessor(js, binary, prim['attributes']['POSITION'])
            if skin and 'JOINTS_0' in prim['attributes']:
                joints = accessor(js, binary, prim['attributes']['JOINTS_0'])
                weights = accessor(js, binary, prim['attributes']['WEIGHTS_0'])
                rest = []
                for p, jj, ww in zip(pos, joints, weights):
                    s = sum(ww)
                    if not math.isfinite(s) or s <= 0.0:
                        # Weights the file leaves unreadable (NaN): where every joint
                        # at rest puts it, the first joint's bind.
                        rest.append(apply(jm[0], p))
                        continue
                    acc = [0.0, 0.0, 0.0]
                    for j, wt in zip(jj, ww):
                        if wt:
                            q = apply(jm[j], p)
                            acc = [acc[0] + wt / s * q[0], acc[1] + wt / s * q[1], acc[2] + wt / s * q[2]]
                    rest.append(tuple(acc))
            else:
                rest = [apply(world[i], p) for p in pos]
            if 'indices' in prim:
                idx = [v[0] for v in accessor(js, binary, prim['indices'])]
            else:
                idx = list(range(len(pos)))
            tris = [tuple(idx[k:k + 3]) for k in range(0, len(idx) - 2, 3)]
            out.append((rest, tris))
    return out


def joints_at_rest(js):
    """Every skin joint's (name, world position, parent joint name), first skin wins per name."""
    world = world_matrices(js)
    nodes = js['nodes']
    parent = parents(js)
    seen = {}
    for skin in js.get('skins', []):
        for j in skin['joints']:
            name = nodes[j].get('name', f'joint {j}')
            if name in seen:
                continue
            p = parent.get(j)
            seen[name] = (tuple(world[j][12:15]), nodes[p].get('name') if p is not None else None)
    return seen
