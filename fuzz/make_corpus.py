#!/usr/bin/env python3
"""Writes the hand-made seed corpus in fuzz/corpus/<harness>/ (committed; rerun to refresh).

Each harness's first input byte picks what the rest is: see the harness's opening comment.
"""
import base64
import json
import os
import random
import struct
import subprocess
import sys

root = os.path.dirname(os.path.abspath(__file__))
proto_dir = os.path.join(root, "..", "proto")


def put(harness, name, data):
    folder = os.path.join(root, "corpus", harness)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def encode(message, text):
    return subprocess.run(["protoc", "--proto_path=" + proto_dir, "--encode=lixel.v1." + message,
                           "lixel/v1/lixel.proto"], input=text.encode(), check=True,
                          capture_output=True).stdout


# fuzz_request_decode: 0 SolveRequest, 1 PlanRequest, 2 Scene (text format, then binary).
# A 60-degree perspective viewer looking down -z from z = 5 (row-major Mat4).
viewer = "viewer { m: [1.732, 0, 0, 0, 0, 1.732, 0, 0, 0, 0, -1.001, 4.905, 0, 0, -1, 5] }"
camera = "{ %s width: 64 height: 48 }" % viewer
bounds = "{ min { x: -2 y: -2 z: -2 } max { x: 2 y: 2 z: 2 } }"
solve = f"""views {camera}
planes {{ name: "floor" plane {{ y: 1 w: 1 }} }}
planes {{ name: "table" plane {{ y: 1 w: -0.5 }}
          polygon {{ x: -1 y: 0.5 z: -1 }} polygon {{ x: -1 y: 0.5 z: 1 }}
          polygon {{ x: 1 y: 0.5 z: 1 }} polygon {{ x: 1 y: 0.5 z: -1 }} }}
lights {{ position {{ x: 1 y: 6 z: 2 w: 1 }} }}
lights {{ position {{ x: 0.3 y: 1 z: 0.2 w: 0 }} }}
bounds {bounds}
twist: TWIST_MINIMIZE_AREA scale: 0.5 lixel_budget: 4096
"""
put("fuzz_request_decode", "solve", b"\x00" + encode("SolveRequest", solve))
plan = f"""objects {{ name: "box" bounds {bounds} closed: true }}
camera {camera}
light {{ position {{ x: 1 y: 6 z: 2 w: 1 }} }}
planes {{ name: "floor" plane {{ y: 1 w: 2 }} }}
lixel_budget: 65536 fallback_floor: 1024 max_texture_size: 2048
passes {{ second_depth: true silhouette_map: true volumes: true }}
"""
put("fuzz_request_decode", "plan", b"\x01" + encode("PlanRequest", plan))
# The same plan with its objects packed: two boxes, six values each, one named.
plan_packed = plan.replace(
    f'objects {{ name: "box" bounds {bounds} closed: true }}',
    'packed_objects { bounds: [-2, -2, -2, 2, 2, 2, -1, 0, -1, 0, 1, 0] '
    'names: ["box", ""] closed: [true, false] }')
assert plan_packed != plan, "the seed plan's objects changed: packed_objects not substituted"
put("fuzz_request_decode", "plan_packed", b"\x01" + encode("PlanRequest", plan_packed))
put("fuzz_request_decode", "plan_scene",
    b"\x01" + encode("PlanRequest", 'scene_id: "abc" light { position { y: 1 } }'))
cube_positions = ", ".join(str(float(c)) for i in range(8)
                           for c in (i & 1, (i >> 1) & 1, (i >> 2) & 1))
cube_indices = "0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, " \
               "2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5"
scene_text = f"""name: "cube"
meshes {{ name: "cube" positions: [{cube_positions}] indices: [{cube_indices}] closed: true }}
planes {{ name: "floor" plane {{ y: 1 }} }}
default_camera {camera}
default_light {{ position {{ x: 1 y: 6 z: 2 w: 1 }} }}
"""
put("fuzz_request_decode", "scene", b"\x02" + encode("Scene", scene_text))

# fuzz_mesh_load: 0 OBJ, 1 glTF JSON, 2 GLB, 3 scene file.
obj = (b"o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n"
       b"o quad\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 4 5 6 7\ng rest\nf -1 -2 -3\n")
put("fuzz_mesh_load", "obj", b"\x00" + obj)
positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
indices = struct.pack("<3H", 0, 1, 2) + b"\0\0"
binary = positions + indices


def gltf(uri):
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [1, 2, 3], "scale": [-1, 1, 1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "buffers": [{"byteLength": len(binary)}],
    }
    if uri:
        doc["buffers"][0]["uri"] = uri
    return json.dumps(doc, separators=(",", ":")).encode()


put("fuzz_mesh_load", "gltf",
    b"\x01" + gltf("data:application/octet-stream;base64," + base64.b64encode(binary).decode()))
chunk = gltf(None)
chunk += b" " * (-len(chunk) % 4)
glb = (struct.pack("<II", len(chunk), 0x4E4F534A) + chunk +
       struct.pack("<II", len(binary), 0x004E4942) + binary)
put("fuzz_mesh_load", "glb", b"\x02" + struct.pack("<4sII", b"glTF", 2, 12 + len(glb)) + glb)
scene_file = b"""# a cube on a floor
name seed
mesh cube.obj closed
plane table 0 1 0 -1
polygon 0 1 0  0 1 1  1 1 1  1 1 0
plane floor 0 1 0 0
eye 3 4 5
target 0.5 0.5 0.5
up 0 1 0
fov 50
near 0.1
far 50
size 64 48
light point 1 6 2
"""
put("fuzz_mesh_load", "scene", b"\x03" + scene_file)
put("fuzz_mesh_load", "scene_directional",
    b"\x03mesh cube.obj\nplane floor 0 1 0 0\nlight directional 0.3 1 0.2\n")

# fuzz_upload: the upload limit in KiB (2 bytes), then records: kind (even header, odd data),
# a 16-bit little-endian length, the bytes.
def record(kind, payload):
    return struct.pack("<BH", kind, len(payload)) + payload


def upload(fmt, content, pieces, planes=""):
    header = encode("SceneHeader", "format: %s total_bytes: %d %s" % (fmt, len(content), planes))
    out = struct.pack("<H", 63) + record(0, header)
    step = -(-len(content) // pieces)
    for i in range(0, len(content), step):
        out += record(1, content[i:i + step])
    return out


scene_bytes = encode("Scene", scene_text)
floor = 'planes { name: "floor" plane { y: 1 } }'
put("fuzz_upload", "lixel", upload("SCENE_FORMAT_LIXEL", scene_bytes, 3))
put("fuzz_upload", "obj", upload("SCENE_FORMAT_OBJ", obj, 2, floor))
put("fuzz_upload", "gltf", upload("SCENE_FORMAT_GLTF", gltf(
    "data:application/octet-stream;base64," + base64.b64encode(binary).decode()), 1, floor))
put("fuzz_upload", "glb", upload("SCENE_FORMAT_GLTF",
                                 struct.pack("<4sII", b"glTF", 2, 12 + len(glb)) + glb, 2, floor))
put("fuzz_upload", "short", upload("SCENE_FORMAT_LIXEL", scene_bytes, 2)[:-20])
put("fuzz_upload", "two_headers", upload("SCENE_FORMAT_OBJ", obj, 1) +
    record(0, encode("SceneHeader", "format: SCENE_FORMAT_OBJ total_bytes: 1")))

# fuzz_solver and fuzz_scheduler read FuzzedDataProvider streams (integers from the end, bytes
# from the front): seeds are fixed pseudo-random streams of a few lengths, one per entry point.
rng = random.Random(12351)
for harness, count in (("fuzz_solver", 5), ("fuzz_scheduler", 4)):
    for i in range(count):
        data = bytearray(rng.randrange(256) for _ in range(96 + 64 * i))
        data[-1] = i  # the first byte consumed: which entry point (fuzz_solver)
        put(harness, "seed%d" % i, bytes(data))
# fuzz_session_decode: SessionRequest messages read from the front, each length (two bytes, most
# significant read first) and, after an accepted frame, a count of served ids (one byte) read from
# the end.
def session(messages):
    front, reads = b"", []
    for message, accepted in messages:
        front += message
        reads += [len(message) >> 8, len(message) & 0xFF]
        if accepted:
            reads.append(0)
    return front + bytes(reversed(reads))


identity = "object_to_world { m: [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1] }"
lifted = "object_to_world { m: [1,0,0,0, 0,1,0,0, 0,0,1,0, 0.5,0.25,0,1] }"
mirrored = "object_to_world { m: [-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1] }"
open_text = ('open { plan { scene_id: "fuzz" lixel_budget: 4096 fallback_floor: 1024 '
             'camera %s light { position { x: 1 y: 6 z: 2 w: 1 } } coherence {} } '
             'encoding { codec: MAP_CODEC_QUANTISED } max_frames_ahead: 2 }' % camera)
frame_text = ('frame { number: %d instances { instances { mesh: "quad" %s } '
              'instances { mesh: "triangle" %s } instances { mesh: "triangle" %s } } }')
opened = encode("SessionRequest", open_text)
put("fuzz_session_decode", "frames", session([
    (opened, False),
    (encode("SessionRequest", frame_text % (1, identity, lifted, mirrored)), True),
    (encode("SessionRequest", "frame { number: 2 camera %s }" % camera), True),
    (encode("SessionRequest", frame_text % (3, identity, identity, lifted)), True)]))
put("fuzz_session_decode", "refusals", session([
    (encode("SessionRequest", frame_text % (1, identity, lifted, mirrored)), False),
    (opened, False),
    (opened, False),
    (encode("SessionRequest", frame_text % (5, identity, lifted, mirrored)), True),
    (encode("SessionRequest", frame_text % (4, identity, lifted, mirrored)), False),
    (encode("SessionRequest", 'frame { number: 6 instances { instances { mesh: "cube" } } }'),
     False),
    (encode("SessionRequest", "frame { number: 7 instances {} }"), True)]))
viewed = encode("SessionRequest", open_text[:-2] +
                ' view { filter: FILTER_VOLUMES evaluate: true } }')
put("fuzz_session_decode", "view", session([
    (encode("SessionRequest", open_text[:-2] + ' view { plan { scene_id: "fuzz" } } }'), False),
    (viewed, False),
    (encode("SessionRequest", frame_text % (1, identity, lifted, mirrored)), True),
    (encode("SessionRequest", "frame { number: 2 camera %s }" % camera), True)]))
print("corpus written under", os.path.join(root, "corpus"), file=sys.stderr)
