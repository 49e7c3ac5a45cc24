#!/usr/bin/python3
"""The Python client against a hostile server: a fake Shadow service (grpcio, in this process)
whose Session answers with malformed streams, each of which lixel_client.Session must refuse
with a StreamError naming the part it got wrong, never returning a frame or taking in more than
its receive bound. Run with the build's Python folder (stubs and package) first on sys.path."""

import sys
from concurrent import futures

sys.path.insert(0, sys.argv[1])

import grpc  # noqa: E402
import lixel_client  # noqa: E402
from lixel.v1 import lixel_pb2 as pb  # noqa: E402
from lixel.v1 import lixel_pb2_grpc as pb_grpc  # noqa: E402


def header(*images):
    h = pb.RenderHeader()
    for width, height, coded in images:
        h.images.add(map_index=0, width=width, height=height, coded=coded,
                     bytes=0 if coded else width * height * 4)
    return pb.SessionResponse(frame=1, header=h)


def chunk(index, offset, data):
    return pb.SessionResponse(frame=1, chunk=pb.MapChunk(image_index=index, offset=offset,
                                                         data=data))


DONE = pb.SessionResponse(frame=1, done=pb.FrameDone(code=0))

# Each case: the responses the fake server streams, and what the error must name.
CASES = {
    "chunk before header": ([chunk(0, 0, b"\0" * 16), DONE], "chunk: before the frame's header"),
    "unknown image": ([header((2, 2, False)), chunk(3, 0, b"\0" * 16), DONE],
                      "image_index 3 names no image"),
    "past the image": ([header((2, 2, False)), chunk(0, 8, b"\0" * 16), DONE],
                       "images[0]: chunk at 8 is out of order or runs past the image's 16 bytes"),
    "out of order": ([header((2, 2, False)), chunk(0, 4, b"\0" * 4), DONE],
                     "images[0]: chunk at 4 is out of order"),
    "short image": ([header((2, 2, False)), chunk(0, 0, b"\0" * 8), DONE],
                    "images[0]: 8 of its 16 bytes arrived"),
    "no header": ([DONE], "no header before the frame's end"),
    "huge announce": ([header((16385, 16385, False), (16385, 16385, False)), DONE],
                      "header: 2147745800 bytes of maps announced, over max_receive_bytes"),
    "outside sides": ([header((0, 5, False)), DONE], "images[0]: 0 x 5 is outside"),
    "coded unasked": ([header((2, 2, True)), DONE], "images[0]: coded, but no encoding"),
    "second header": ([header((2, 2, False)), header((2, 2, False)), DONE],
                      "header: a second header in one frame"),
    "interleaved": ([header((2, 2, False)), pb.SessionResponse(frame=2, done=pb.FrameDone())],
                    "frame 2 began before frame 1 was done"),
}


class Hostile(pb_grpc.ShadowServicer):
    def Session(self, request_iterator, context):
        first = next(request_iterator)
        yield from CASES[first.open.plan.scene_id][0]


def main() -> int:
    server = grpc.server(futures.ThreadPoolExecutor(max_workers=4))
    pb_grpc.add_ShadowServicer_to_server(Hostile(), server)
    port = server.add_insecure_port("127.0.0.1:0")
    server.start()
    stub, metadata = lixel_client.connect(f"127.0.0.1:{port}")
    failed = 0
    for name, (_, expected) in CASES.items():
        open_message = pb.SessionOpen()
        open_message.plan.scene_id = name
        session = lixel_client.Session(stub, open_message, metadata, timeout=30)
        session.close()
        try:
            frame = next(iter(session))
            print(f"{name}: returned frame {frame.number}, expected a StreamError")
            failed += 1
        except lixel_client.StreamError as error:
            if expected not in str(error):
                print(f"{name}: '{error}' does not name '{expected}'")
                failed += 1
            else:
                print(f"{name}: refused: {error}")
    server.stop(0)
    print(f"{len(CASES) - failed} of {len(CASES)} malformed streams refused by name")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
