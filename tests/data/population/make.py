#!/usr/bin/env python3
"""Writes the labelled population from Quaternius's rigged characters (CC0).

For each character: NAME.glb, its surface at rest (each vertex where the file's skin puts it
with no clip playing; positions and triangles only, one primitive per piece), and NAME.toml,
its labels: every joint the artist's rig places (its rest position) that a puppeteer turns,
by role, with up (+y, glTF's), front (from the rig's left and right joints) and its half.

    python3 make.py SOURCE_DIR   # SOURCE_DIR: quaternius-showcase @ eab2e43, public/glb
"""
import json, math, os, struct, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gltf import read_glb, rest_meshes, joints_at_rest, world_matrices

HERE = os.path.dirname(os.path.abspath(__file__))

# (file under public/glb, name, kind, family)
CHARACTERS = [
    ('animals_pack/Alpaca.glb', 'alpaca', 'quadruped', 'animal'),
    ('animals_pack/Bull.glb', 'bull', 'quadruped', 'animal'),
    ('animals_pack/Cow.glb', 'cow-low-poly', 'quadruped', 'animal'),
    ('animals_pack/Deer.glb', 'deer', 'quadruped', 'animal'),
    ('animals_pack/Donkey.glb', 'donkey', 'quadruped', 'animal'),
    ('animals_pack/Fox.glb', 'fox', 'quadruped', 'animal'),
    ('animals_pack/Horse.glb', 'horse-low-poly', 'quadruped', 'animal'),
    ('animals_pack/Husky.glb', 'husky', 'quadruped', 'animal'),
    ('animals_pack/ShibaInu.glb', 'shiba', 'quadruped', 'animal'),
    ('animals_pack/Stag.glb', 'stag', 'quadruped', 'animal'),
    ('animals_pack/Wolf.glb', 'wolf', 'quadruped', 'animal'),
    ('dinosaurs_pack/Apatosaurus.glb', 'apatosaurus', 'quadruped with a tail', 'dino'),
    ('dinosaurs_pack/Stegosaurus.glb', 'stegosaurus', 'quadruped with a tail', 'dino'),
    ('dinosaurs_pack/Triceratops.glb', 'triceratops', 'quadruped with a tail', 'dino'),
    ('dinosaurs_pack/Parasaurolophus.glb', 'parasaurolophus', 'biped with a tail', 'dino'),
    ('dinosaurs_pack/Trex.glb', 'trex', 'biped with a tail', 'dino'),
    ('dinosaurs_pack/Velociraptor.glb', 'velociraptor', 'biped with a tail', 'dino'),
    ('easy_enemies_pack/Rat.glb', 'rat', 'quadruped', 'dino'),
    ('easy_enemies_pack/Frog.glb', 'frog', 'amphibian', 'frog'),
    ('easy_enemies_pack/Spider.glb', 'spider', 'spider', 'spider'),
    ('easy_enemies_pack/Wasp.glb', 'wasp', 'insect', 'wasp'),
    ('easy_enemies_pack/Snake.glb', 'snake', 'snake', 'snake'),
    ('fish_pack/Dolphin.glb', 'dolphin', 'fish', 'fish'),
    ('fish_pack/Whale.glb', 'whale', 'fish', 'fish'),
    ('fish_pack/Manta_ray.glb', 'manta', 'fish', 'fish'),
    ('fish_pack/Shark.glb', 'shark', 'fish', 'fish'),
    ('fish_pack/Fish1.glb', 'fish1', 'fish', 'fish'),
    ('fish_pack/Fish2.glb', 'fish2', 'fish', 'fish'),
    ('fish_pack/Fish3.glb', 'fish3', 'fish', 'fish'),
    ('mech_pack/George.glb', 'mech-george', 'robot', 'humanoid'),
    ('mech_pack/Leela.glb', 'mech-leela', 'robot', 'humanoid'),
    ('mech_pack/Mike.glb', 'mech-mike', 'robot', 'humanoid'),
    ('mech_pack/Stan.glb', 'mech-stan', 'robot', 'humanoid'),
    ('single_knight_pack/KnightCharacter.glb', 'knight', 'humanoid', 'humanoid'),
    ('modular_men/Adventurer.glb', 'man-adventurer', 'humanoid', 'humanoid'),
    ('modular_men/Casual2.glb', 'man-casual2', 'humanoid', 'humanoid'),
    ('modular_men/Farmer.glb', 'man-farmer', 'humanoid', 'humanoid'),
    ('modular_men/King.glb', 'man-king', 'humanoid', 'humanoid'),
    ('modular_men/Spacesuit.glb', 'man-spacesuit', 'humanoid', 'humanoid'),
    ('modular_women/Adventurer.glb', 'woman-adventurer', 'humanoid', 'humanoid'),
    ('modular_women/Casual.glb', 'woman-casual', 'humanoid', 'humanoid'),
    ('modular_women/Formal.glb', 'woman-formal', 'humanoid', 'humanoid'),
    ('modular_women/Medieval.glb', 'woman-medieval', 'humanoid', 'humanoid'),
    ('modular_women/Witch.glb', 'woman-witch', 'humanoid', 'humanoid'),
    ('modular_women/Worker.glb', 'woman-worker', 'humanoid', 'humanoid'),
]

R, O = True, False
# Per rig family: joint name (side as `.S`) -> (role, required). Joints not named are
# not turned by a puppeteer (a shoulder blade's bone inside the body, an IK target).
ROLES = {
    'humanoid': {
        'Neck': ('neck', R), 'Head': ('head', O),
        'UpperArm.S': ('arm.S', R), 'LowerArm.S': ('forearm.S', R), 'Hand.S': ('hand.S', O),
        'UpperLeg.S': ('leg.S', R), 'LowerLeg.S': ('shin.S', R), 'Foot.S': ('foot.S', O),
    },
    'animal': {
        'Neck1': ('neck', R), 'Head': ('head', O), 'Ear1.S': ('ear.S', O), 'Tail1': ('tail', O),
        'FrontUpperLeg.S': ('arm.S', R), 'FrontLowerLeg.S': ('forearm.S', R),
        'BackLeg.S': ('leg.S', R), 'BackUpperLeg.S': ('shin.S', R), 'BackLowerLeg.S': ('foot.S', O),
    },
    'dino': {
        'Neck': ('neck', R), 'Head': ('head', O), 'Tail1': ('tail', O),
        'FrontUpLeg.S': ('arm.S', R), 'FrontLowLeg.S': ('forearm.S', R), 'FrontFoot.S': ('hand.S', O),
        'BackUpLeg.S': ('leg.S', R), 'BackLowLeg.S': ('shin.S', R), 'BackFoot.S': ('foot.S', O),
    },
    'frog': {
        'Neck': ('neck', O), 'Head': ('head', O),
        'FrontUpLeg.S': ('arm.S', R), 'FrontLowLeg.S': ('forearm.S', R),
        'BackLeg.S': ('leg.S', R), 'BackUpLeg.S': ('shin.S', R), 'BackLowLeg.S': ('foot.S', O),
    },
    'spider': {
        'Head': ('head', O), 'Abdomen': ('abdomen', O),
        'FrontLeg.S': ('leg1.S', R), 'FrontLeg2.S': ('shin1.S', R),
        'MidFrontLeg.S': ('leg2.S', R), 'MidFrontLeg2.S': ('shin2.S', R),
        'MidBackLeg.S': ('leg3.S', R), 'MidBackLeg2.S': ('shin3.S', R),
        'BackLeg.S': ('leg4.S', R), 'BackLeg2.S': ('shin4.S', R),
    },
    'wasp': {
        'Neck': ('neck', O), 'Head': ('head', O), 'Abdomen': ('abdomen', O),
        'Wing.S': ('wing.S', O),
        'TopLeg1.S': ('leg1.S', R), 'TopLeg2.S': ('shin1.S', R),
        'MidLeg1.S': ('leg2.S', R), 'MidLeg2.S': ('shin2.S', R),
        'BottomLeg1.S': ('leg3.S', R), 'BottomLeg2.S': ('shin3.S', R),
    },
    'snake': {'Head': ('head', O), 'LowerMouth': ('jaw', O)},
    'fish': {
        'Tail': ('tail', O), 'TopFlipper.S': ('fin.S', O), 'Fin.S': ('fin.S', O),
        'Bone': ('fin.X', O), 'Bone.001': ('fin.X', O),
    },
}
# Chains along which any cut is fair (a tail, a neck, a finger, an ear, a spine), by their
# first joint's name; each runs through its first child (by the rig's order) to its end,
# and on past it by its last bone's length.
FREE = ['Tail1', 'Tail', 'Neck1', 'Neck', 'Ear1.S', 'Hips', 'Body', 'Back', 'Spine1', 'Root',
        'Abdomen', 'Chest', 'Thumb1.S', 'Index1.S', 'Middle1.S', 'Ring1.S', 'Pinky1.S',
        'Thumb2.S', 'Index2.S', 'Middle2.S', 'Ring2.S', 'Pinky2.S', 'PalmP.S', 'PalmR.S',
        'PalmI.S', 'PalmT.S', 'FrontLeg3.S', 'MidFrontLeg3.S', 'MidBackLeg3.S', 'BackLeg3.S',
        'TopLeg3.S', 'MidLeg3.S', 'BottomLeg3.S', 'Wing.S', 'TopFlipper.S', 'Fin.S', 'Bone',
        'Bone.001', 'Mouth', 'Torso', 'Shoulders', 'Thorax', 'Sting', 'FrontLowerLeg.S',
        'BackLowerLeg.S', 'FrontFoot.S', 'BackFoot.S', 'Hand.S', 'Foot.S', 'Head']


def sides(pattern):
    if '.S' in pattern:
        return [(pattern.replace('.S', '.L'), 'L'), (pattern.replace('.S', '.R'), 'R')]
    return [(pattern, None)]


def r3(v):
    return [round(x, 4) for x in v]


def write_glb(path, pieces):
    """A static glb: one mesh, one primitive per piece, positions and u32 indices."""
    binary = bytearray()
    views, accessors, prims = [], [], []
    for pos, tris in pieces:
        lo = [min(p[k] for p in pos) for k in range(3)]
        hi = [max(p[k] for p in pos) for k in range(3)]
        off = len(binary)
        for p in pos:
            binary += struct.pack('<3f', *p)
        views.append({'buffer': 0, 'byteOffset': off, 'byteLength': len(binary) - off, 'target': 34962})
        accessors.append({'bufferView': len(views) - 1, 'componentType': 5126, 'count': len(pos),
                          'type': 'VEC3', 'min': lo, 'max': hi})
        off = len(binary)
        for t in tris:
            binary += struct.pack('<3I', *t)
        views.append({'buffer': 0, 'byteOffset': off, 'byteLength': len(binary) - off, 'target': 34963})
        accessors.append({'bufferView': len(views) - 1, 'componentType': 5125, 'count': 3 * len(tris),
                          'type': 'SCALAR'})
        prims.append({'attributes': {'POSITION': len(accessors) - 2}, 'indices': len(accessors) - 1})
    js = {'asset': {'version': '2.0', 'generator': 'puppet tests/data/population/make.py'},
          'scene': 0, 'scenes': [{'nodes': [0]}], 'nodes': [{'mesh': 0, 'name': 'rest'}],
          'meshes': [{'primitives': prims}], 'accessors': accessors, 'bufferViews': views,
          'buffers': [{'byteLength': len(binary)}]}
    j = json.dumps(js, separators=(',', ':')).encode()
    j += b' ' * (-len(j) % 4)
    binary += b'\0' * (-len(binary) % 4)
    out = struct.pack('<III', 0x46546C67, 2, 12 + 8 + len(j) + 8 + len(binary))
    out += struct.pack('<II', len(j), 0x4E4F534A) + j + struct.pack('<II', len(binary), 0x004E4942) + binary
    open(path, 'wb').write(out)


def axis(v):
    a = [abs(x) for x in v]
    k = a.index(max(a))
    return ('-' if v[k] < 0 else '+') + 'xyz'[k]


def main(src):
    # Halves, fixed once: alternate down the list within each rig family (families of
    # fewer than four together), so each half has every kind.
    count = {}
    for c in CHARACTERS:
        count[c[3]] = count.get(c[3], 0) + 1
    group = {c[1]: c[3] if count[c[3]] >= 4 else 'other' for c in CHARACTERS}
    members = {}
    for c in CHARACTERS:
        members.setdefault(group[c[1]], []).append(c[1])
    rows = []
    for file, name, kind, family in CHARACTERS:
        js, binary = read_glb(os.path.join(src, file))
        pieces = rest_meshes(js, binary)
        write_glb(os.path.join(HERE, name + '.glb'), pieces)
        joints = joints_at_rest(js)
        pts = [p for pos, _ in pieces for p in pos]
        lo = [min(p[k] for p in pts) for k in range(3)]
        children = {}
        for n, (_, parent) in joints.items():
            children.setdefault(parent, []).append(n)
        labelled = []
        for pattern, (role, required) in ROLES[family].items():
            for jname, side in sides(pattern):
                if jname not in joints:
                    continue
                at = joints[jname][0]
                r = role
                if side:
                    r = role.replace('.S', '.' + side)
                if '.X' in r:
                    # A pair the rig names without sides: left is +x (glTF: front +z, up +y).
                    r = r.replace('.X', '.L' if at[0] > 0 else '.R')
                labelled.append((r, at, required))
        # Up is glTF's +y; left from the rig's pairs, front = left x up.
        pairs = [(joints[n][0], joints[n[:-2] + '.R'][0]) for n in joints
                 if n.endswith('.L') and n[:-2] + '.R' in joints]
        front = None
        if pairs:
            left = [sum(l[k] - r[k] for l, r in pairs) for k in range(3)]
            front = axis([-left[2], 0.0, left[0]])  # left x (0, 1, 0)
        else:
            head = next((joints[n][0] for n in ('Face', 'Head') if n in joints), None)
            tail = next((joints[n][0] for n in ('Tail',) if n in joints), None)
            if head and tail and family == 'fish':
                front = axis([head[0] - tail[0], 0.0, head[2] - tail[2]])
        free = []
        for pattern in FREE:
            for jname, _ in sides(pattern):
                if jname not in joints:
                    continue
                chain = [jname]
                while children.get(chain[-1]):
                    chain.append(children[chain[-1]][0])
                at = [joints[n][0] for n in chain]
                if len(at) >= 2:
                    last = [2 * at[-1][k] - at[-2][k] for k in range(3)]
                elif pattern in ('FrontLowerLeg.S', 'BackLowerLeg.S', 'FrontFoot.S', 'BackFoot.S',
                                 'Foot.S'):
                    last = [at[-1][0], lo[1], at[-1][2]]  # on to the ground
                else:
                    continue
                free.append((jname, at + [last]))
        half = 'development' if members[group[name]].index(name) % 2 == 0 else 'held-out'
        source = 'public/glb/' + file
        lines = [f'# {name}: Quaternius (quaternius.com), CC0 1.0, from github.com/trebeljahr/quaternius-showcase',
                 f'# @ eab2e43 : {source}. Written by make.py: the surface at rest, and the joints of the',
                 '# artist\'s rig that a puppeteer turns, by role.',
                 f'mesh = "{name}.glb"', f'kind = "{kind}"', 'up = "+y"']
        if front:
            lines.append(f'front = "{front}"')
        lines += [f'half = "{half}"', f'credit = "Quaternius, CC0 1.0 ({source})"', '']
        for role, at, required in labelled:
            lines += ['[[joint]]', f'role = "{role}"', f'at = {r3(at)}', f'required = {str(required).lower()}', '']
        for jname, along in free:
            lines += ['[[free]]', f'role = "{jname}"', 'along = [' + ', '.join(str(r3(p)) for p in along) + ']', '']
        open(os.path.join(HERE, name + '.toml'), 'w').write('\n'.join(lines))
        rows.append((name, kind, half, len(pts), len(pieces), sum(1 for l in labelled if l[2]), front, source))
        print(name, kind, half, len(pts), 'verts', len(pieces), 'pieces',
              sum(1 for l in labelled if l[2]), 'required', len(labelled), 'joints', 'front', front)
    return rows


if __name__ == '__main__':
    main(sys.argv[1])
