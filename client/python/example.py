#!/usr/bin/python3
"""A lixel client in Python: upload a small scene, plan its shadow maps, render them (raw, then
coded and decoded with lixel_maps) and fetch a view mask, printing what the server answered.
Uses Debian's python3-grpcio, python3-numpy and python3-zstandard, and the stubs the build
generates from proto/lixel/v1/lixel.proto (build/client/python).

    python3 client/python/example.py --target 127.0.0.1:50051 --stubs build/client/python
"""

import argparse
import array
import math
import os
import sys


def render_images(stub, request, metadata):
    """A Render call's images as (MapImage, bytes) in stream order: raw float32, or coded."""
    images = []
    for part in stub.Render(request, metadata=metadata, timeout=120):
        if part.HasField("header"):
            images = [(meta, bytearray()) for meta in part.header.images]
        else:
            chunk = part.chunk
            images[chunk.image_index][1][chunk.offset:chunk.offset + len(chunk.data)] = chunk.data
    return [(meta, bytes(data)) for meta, data in images]


def perspective_look_at(eye, target, fovy_degrees, aspect, near, far):
    """World -> clip with [0, 1] clip depth, column-major, as lixel's solver builds it."""
    f = [t - e for t, e in zip(target, eye)]
    n = math.sqrt(sum(c * c for c in f))
    f = [c / n for c in f]
    up = (0.0, 1.0, 0.0)
    s = [f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0]]
    n = math.sqrt(sum(c * c for c in s))
    s = [c / n for c in s]
    u = [s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]]
    view = [
        [s[0], s[1], s[2], -sum(a * b for a, b in zip(s, eye))],
        [u[0], u[1], u[2], -sum(a * b for a, b in zip(u, eye))],
        [-f[0], -f[1], -f[2], sum(a * b for a, b in zip(f, eye))],
        [0.0, 0.0, 0.0, 1.0],
    ]
    g = 1.0 / math.tan(math.radians(fovy_degrees) / 2.0)
    proj = [
        [g / aspect, 0.0, 0.0, 0.0],
        [0.0, g, 0.0, 0.0],
        [0.0, 0.0, -far / (far - near), -far * near / (far - near)],
        [0.0, 0.0, -1.0, 0.0],
    ]
    m = [[sum(proj[r][k] * view[k][c] for k in range(4)) for c in range(4)] for r in range(4)]
    return [m[r][c] for c in range(4) for r in range(4)]  # column-major


def box(pb, name, lo, hi):
    """A closed box mesh, outward-facing counter-clockwise triangles."""
    mesh = pb.Mesh(name=name, closed=True)
    corners = [(x, y, z) for z in (lo[2], hi[2]) for y in (lo[1], hi[1]) for x in (lo[0], hi[0])]
    for c in corners:
        mesh.positions.extend(c)
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    for a, b, c, d in faces:
        mesh.indices.extend([a, b, c, a, c, d])
    return mesh


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--target", default="127.0.0.1:50051")
    parser.add_argument("--stubs", default="build/client/python",
                        help="folder holding the generated lixel/v1 stubs")
    parser.add_argument("--token", default="", help="bearer token, when the server wants one")
    args = parser.parse_args()

    sys.path.insert(0, args.stubs)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # lixel_maps
    import grpc
    from lixel.v1 import lixel_pb2 as pb
    from lixel.v1 import lixel_pb2_grpc as rpc

    channel = grpc.insecure_channel(args.target, options=[
        ("grpc.max_receive_message_length", 256 << 20)])
    stub = rpc.ShadowStub(channel)
    metadata = [("authorization", "Bearer " + args.token)] if args.token else []

    scene = pb.Scene(name="python example")
    scene.meshes.append(box(pb, "floor", (-10, -0.1, -10), (10, 0, 10)))
    scene.meshes.append(box(pb, "crate", (-1, 0, -1), (1, 1.5, 1)))
    scene.planes.append(pb.PlaneOfInterest(name="floor", plane=pb.Vec4(y=1.0)))
    scene.default_light.position.CopyFrom(pb.Vec4(x=4, y=9, z=3, w=1))
    scene.default_camera.viewer.m.extend(perspective_look_at((0, 4, 9), (0, 0, 0), 60, 1, 0.1, 100))
    scene.default_camera.width = 256
    scene.default_camera.height = 256
    content = scene.SerializeToString()

    def chunks():
        yield pb.SceneChunk(header=pb.SceneHeader(format=pb.SCENE_FORMAT_LIXEL,
                                                  total_bytes=len(content)))
        for offset in range(0, len(content), 1 << 20):
            yield pb.SceneChunk(data=content[offset:offset + (1 << 20)])

    try:
        uploaded = stub.UploadScene(chunks(), metadata=metadata, timeout=60)
        print(f"scene {uploaded.scene_id} ({uploaded.triangles} triangles) on {uploaded.instance}")

        plan_request = pb.PlanRequest(scene_id=uploaded.scene_id, lixel_budget=256 * 256)
        plan = stub.Plan(plan_request, metadata=metadata, timeout=60)
        for m in plan.maps:
            print(f"  map {m.name}: {m.map.width} x {m.map.height} lixels")
        for item in plan.left_out:
            print(f"  left out {item.item}: {item.reason}")

        raw = render_images(stub, pb.RenderRequest(plan=plan_request), metadata)
        received = sum(len(image) for _, image in raw)
        print(f"  rendering {len(raw)} image(s)")
        print(f"  received {received} bytes of maps")

        # The same maps coded (docs/service.md, "Coded maps"), decoded with lixel_maps.
        import numpy
        import lixel_maps
        coded_request = pb.RenderRequest(plan=plan_request, encoding=pb.MapEncoding(
            codec=pb.MAP_CODEC_QUANTISED))
        coded = render_images(stub, coded_request, metadata)
        streamed = sum(len(image) for _, image in coded)
        worst = 0.0
        for (_, raw_bytes), (meta, coded_bytes) in zip(raw, coded):
            decoded = lixel_maps.decode(coded_bytes)
            exact = numpy.frombuffer(raw_bytes, dtype=numpy.float32).reshape(decoded.texels.shape)
            error = float(numpy.abs(decoded.texels.astype(numpy.float64) - exact).max())
            if error > decoded.header.error_bound:
                print(f"lixel: image {meta.map_index} decoded {error} off, over its bound "
                      f"{decoded.header.error_bound}", file=sys.stderr)
                return 1
            worst = max(worst, error)
        print(f"  coded: {streamed} bytes of maps, {received / streamed:.1f}x smaller, decoded "
              f"within each image's stated bound (largest error {worst:.2g})")

        view = stub.View(pb.ViewRequest(plan=plan_request, evaluate=True), metadata=metadata,
                         timeout=120)
        mask = array.array("f")
        mask.frombytes(view.mask)
        lit = sum(1 for v in mask if v >= 0.5)
        print(f"  view {view.width} x {view.height}: {lit} lit pixels; misclassified "
              f"{view.evaluation.misclassified_percent:.3f}% against exact visibility")
    except grpc.RpcError as error:
        print(f"lixel: {error.code().name}: {error.details()}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
