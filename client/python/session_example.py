#!/usr/bin/python3
"""A moving scene through a lixel Session from Python: upload a floor and two boxes once, then
stream frames in which one box slides along the floor (its instance's matrix) and the camera
turns, reading each frame's plan and maps (coded, decoded with lixel_maps) as they come; with
--masks, each frame's shadow mask instead (a thin client that shades with lixel's answer), PCF
over plane-optimal maps, evaluated against exact visibility.

    python3 client/python/session_example.py --target 127.0.0.1:50051
(with the package installed: see the README; or --stubs build/client/python to run from the tree)
"""

import argparse
import math
import os
import sys


def box(pb, name, lo, hi):
    """A closed box mesh, outward-facing counter-clockwise triangles."""
    mesh = pb.Mesh(name=name, closed=True)
    for z in (lo[2], hi[2]):
        for y in (lo[1], hi[1]):
            for x in (lo[0], hi[0]):
                mesh.positions.extend([x, y, z])
    mesh.indices.extend([0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                         2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5])
    return mesh


def viewer(eye, target, aspect=1.0, fovy=60.0, near=0.1, far=100.0):
    """World -> clip with [0, 1] clip depth, rows, as lixel's solver builds it."""
    f = [t - e for t, e in zip(target, eye)]
    n = math.sqrt(sum(c * c for c in f))
    f = [c / n for c in f]
    s = [-f[2], 0.0, f[0]]  # f x up, up = +y
    n = math.sqrt(sum(c * c for c in s))
    s = [c / n for c in s]
    u = [s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]]
    view = [s + [-sum(a * b for a, b in zip(s, eye))], u + [-sum(a * b for a, b in zip(u, eye))],
            [-c for c in f] + [sum(a * b for a, b in zip(f, eye))], [0.0, 0.0, 0.0, 1.0]]
    g = 1.0 / math.tan(math.radians(fovy) / 2.0)
    proj = [[g / aspect, 0, 0, 0], [0, g, 0, 0],
            [0, 0, -far / (far - near), -far * near / (far - near)], [0, 0, -1, 0]]
    return [[sum(proj[r][k] * view[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--target", default="127.0.0.1:50051")
    parser.add_argument("--stubs", default="", help="the build's Python folder, when not installed")
    parser.add_argument("--token", default="")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--masks", action="store_true", help="stream view masks, not maps")
    args = parser.parse_args()
    if args.stubs:
        sys.path.insert(0, args.stubs)
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import numpy
    import lixel_client
    from lixel.v1 import lixel_pb2 as pb

    stub, metadata = lixel_client.connect(args.target, args.token or None)
    scene = pb.Scene(name="python session")
    floor = pb.Mesh(name="floor", positions=[-6, 0, 6, 6, 0, 6, 6, 0, -6, -6, 0, -6],
                    indices=[0, 1, 2, 0, 2, 3])
    scene.meshes.extend([floor, box(pb, "crate", (-0.5, 0, -0.5), (0.5, 1, 0.5)),
                         box(pb, "pillar", (1.5, 0, -1.0), (2.0, 3, -0.5))])
    scene.planes.add(name="floor", plane=pb.Vec4(y=1.0))
    content = scene.SerializeToString()
    chunks = [pb.SceneChunk(header=pb.SceneHeader(total_bytes=len(content)))]
    chunks.append(pb.SceneChunk(data=content))
    uploaded = stub.UploadScene(iter(chunks), metadata=metadata, timeout=60)
    print(f"scene {uploaded.scene_id}: {uploaded.triangles} triangles, uploaded once")

    side = 256
    light = pb.Light(position=pb.Vec4(x=3.0, y=8.0, z=2.0, w=1.0))

    def camera(f):
        a = math.radians(30.0 + f)
        eye = (7.0 * math.sin(a), 4.0, 7.0 * math.cos(a))
        return pb.Camera(viewer=lixel_client.mat4(viewer(eye, (0.0, 0.5, 0.0))), width=side,
                         height=side)

    open_message = pb.SessionOpen()
    open_message.plan.scene_id = uploaded.scene_id
    open_message.plan.lixel_budget = side * side
    open_message.plan.fallback_floor = side * side // 4
    open_message.plan.camera.CopyFrom(camera(0))
    open_message.plan.light.CopyFrom(light)
    open_message.plan.coherence.SetInParent()
    open_message.encoding.codec = pb.MAP_CODEC_QUANTISED
    if args.masks:
        open_message.view.filter = pb.FILTER_PCF
        open_message.view.evaluate = True
    session = lixel_client.Session(stub, open_message, metadata)
    # Send every frame at once (the server holds two ahead and says which it skips), then read.
    for f in range(1, args.frames + 1):
        crate = lixel_client.instance("crate", translation=(-3.0 + 0.3 * f, 0.0, 0.0))
        session.send(f, camera=camera(f), instances=[
            lixel_client.instance("floor"), crate, lixel_client.instance("pillar")])
    session.close()
    served = skipped = 0
    for frame in session:
        skipped += len(frame.skipped)
        if frame.error is not None:
            print(f"frame {frame.number}: refused, {frame.error[1]}", file=sys.stderr)
            return 1
        served += 1
        if args.masks:
            mask = frame.mask
            surface = int(numpy.count_nonzero(mask >= 0))
            lit = int(numpy.count_nonzero(mask > 0.5))
            print(f"frame {frame.number}: mask {mask.shape[1]} x {mask.shape[0]}, "
                  f"{frame.streamed_bytes} bytes, {lit} of {surface} surface pixels lit, "
                  f"{frame.view.evaluation.misclassified_percent:.3f} % misclassified")
            continue
        depth = [texels for meta, texels in frame.images if getattr(meta, "pass") == pb.PASS_DEPTH]
        lit = sum(int(numpy.count_nonzero(d > 0)) for d in depth)
        print(f"frame {frame.number}: {len(frame.plan.maps)} maps, {frame.streamed_bytes} bytes, "
              f"{lit} texels drawn, plan {1e3 * frame.timings.get('plan', 0):.2f} ms, passes "
              f"{1e3 * frame.timings.get('passes', 0):.2f} ms")
    print(f"session: {served} frames served, {skipped} skipped while the client ran ahead")
    return 0 if served > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
