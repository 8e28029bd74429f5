# Checks a glTF written by bk_mesh_tree_save_gltf as Blender imports it
# (Blender's own glTF importer, io_import_scene_gltf2): the object hierarchy
# is the tree's, every object's origin is its node's centre of mass, the
# meshes draw the object once (their triangles are the expected count), the
# materials <name> and <name>_interior are there and used, and every node's
# extras are its custom property "breakables". The expected values come from
# the file itself: its node records (docs/gltf.md) give each node's parent
# and moments, read here with Python's json and struct, not through Blender.
#
#   blender --background --factory-startup --python tests/blender/check_gltf.py -- \
#       FILE.glb|FILE.gltf --nodes N --leaves L --meshes M --triangles T [--material NAME[,NAME...]]
#
# Blender turns glTF's +Y up into its +Z up: a glTF point (x, y, z) is at
# (x, -z, y) in Blender.
import base64
import json
import math
import struct
import sys
import warnings

# Debian's Blender 3.4 importer still says numpy.bool, which numpy 1.24 removed.
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    import numpy

    if "bool" not in numpy.__dict__:
        numpy.bool = bool

import bpy  # noqa: E402 (after the numpy fix)


def fail(message):
    print(f"check_gltf_blender: {message}", file=sys.stderr)
    sys.stdout.flush()
    sys.exit(1)


args = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
if not args:
    fail("usage: blender --background --python check_gltf.py -- FILE --nodes N --leaves L --meshes M --triangles T")
path = args[0]
name = path.rsplit("/", 1)[-1]
expect = {"material": "surface"}
for i in range(1, len(args), 2):
    key = args[i].lstrip("-")
    if i + 1 >= len(args):
        fail(f"{args[i]} needs a value")
    expect[key] = args[i + 1] if key == "material" else int(args[i + 1])
for key in ("nodes", "leaves", "meshes", "triangles"):
    if key not in expect:
        fail(f"--{key} N is required")

# ---------------------------------------------------------------- the file's own records
data = open(path, "rb").read()
if data[:4] == b"glTF":
    json_length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20 : 20 + json_length])
    binary = data[28 + json_length :]
else:
    document = json.loads(data)
    uri = document["buffers"][0]["uri"]
    binary = base64.b64decode(uri.split(",", 1)[1])
ours = document["asset"]["extras"]["breakables"]
view = document["bufferViews"][ours["nodes"]["bufferView"]]
records = binary[view.get("byteOffset", 0) : view.get("byteOffset", 0) + view["byteLength"]]
origin = ours["origin"]
tree = []
for node in range(ours["nodes"]["count"]):
    values = struct.unpack_from("<16d4I", records, 144 * node)
    moments, parent = values[:10], values[16]
    centroid = [origin[k] + moments[1 + k] / moments[0] for k in range(3)]
    size = max(values[13 + k] - values[10 + k] for k in range(3))
    tree.append({"volume": moments[0], "centroid": centroid, "parent": parent, "size": size})

# ---------------------------------------------------------------- Blender's import
bpy.ops.wm.read_factory_settings(use_empty=True)
result = bpy.ops.import_scene.gltf(filepath=path)
if "FINISHED" not in result:
    fail(f"{name}: Blender's glTF importer did not finish ({result})")

objects = [o for o in bpy.data.objects if "breakables" in o.keys()]
by_node = {}
for o in objects:
    extras = o["breakables"]
    node = int(extras["node"])
    if node in by_node:
        fail(f"{name}: two objects carry node {node}")
    by_node[node] = o
    record = tree[node]
    # Node extras arrive as custom properties, with the record's volume.
    if extras["volume"] != record["volume"]:
        fail(f"{name}: {o.name}'s custom property volume {extras['volume']} is not its record's {record['volume']}")
    leaves = list(extras["leaves"])
    if len(leaves) != 2 or not leaves[0] < leaves[1] <= ours["leaf_count"]:
        fail(f"{name}: {o.name}'s custom property leaves {leaves} is not a leaf range")
    # The origin at the centre of mass (glTF +Y up is Blender's +Z up).
    c = record["centroid"]
    want = (c[0], -c[2], c[1])
    got = tuple(o.matrix_world.translation)
    d = math.dist(want, got)
    if not d <= 1e-5 * max(record["size"], 1e-30) + 1e-6 * math.hypot(*want):
        fail(f"{name}: {o.name}'s origin is at {got}, its centre of mass at {want}")

# The hierarchy: an object's parent is its node's parent (none when flat).
flat = ours["levels"] == "leaves"
for node, o in by_node.items():
    parent = tree[node]["parent"]
    want = None if flat or parent == 0xFFFFFFFF else by_node.get(parent)
    if o.parent != want:
        fail(f"{name}: {o.name}'s parent is {o.parent.name if o.parent else None}, expected "
             f"{want.name if want else None}")

mesh_objects = [o for o in objects if o.type == "MESH"]
leaf_objects = [o for o in objects if o.name.startswith("fragment_")]
triangles = sum(len(o.data.polygons) for o in mesh_objects)
if any(len(p.vertices) != 3 for o in mesh_objects for p in o.data.polygons):
    fail(f"{name}: a polygon is not a triangle")
used = {slot.material.name for o in mesh_objects for slot in o.material_slots if slot.material}
counts = {"nodes": len(objects), "leaves": len(leaf_objects), "meshes": len({o.data.name for o in mesh_objects}),
          "triangles": triangles}
for key, value in counts.items():
    if value != expect[key]:
        fail(f"{name}: Blender imports {value} {key}, expected {expect[key]}")
for base in expect["material"].split(","):
    for material in (base, base + "_interior"):
        if material not in used:
            fail(f"{name}: no mesh uses a material named {material} (used: {', '.join(sorted(used))})")
print(f"{name}: Blender {bpy.app.version_string}: {counts['nodes']} objects, {counts['leaves']} fragments, "
      f"{counts['meshes']} meshes, {triangles} triangles, materials {', '.join(sorted(used))}, origins at the "
      "centres of mass: ok")
sys.stdout.flush()
