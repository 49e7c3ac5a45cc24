"""A Session stream in Python: open once, send frames (only what changed), iterate over the
frames the server serves, in order, each with its plan and its maps decoded (raw float32, or
coded maps decoded with lixel_maps against the previous frame's, as the server codes them)."""

from __future__ import annotations

import dataclasses
import queue
from typing import Iterable, Iterator, Optional, Sequence

import grpc
import numpy as np

import lixel_maps
from lixel.v1 import lixel_pb2 as pb
from lixel.v1 import lixel_pb2_grpc as pb_grpc


def connect(target: str, token: Optional[str] = None) -> tuple[pb_grpc.ShadowStub, tuple]:
    """A stub on an insecure channel to `target` and the call metadata carrying `token`."""
    stub = pb_grpc.ShadowStub(grpc.insecure_channel(target))
    metadata = (("authorization", f"Bearer {token}"),) if token else ()
    return stub, metadata


def mat4(rows: Sequence[Sequence[float]]) -> pb.Mat4:
    """A 4 x 4 matrix given by rows, as the wire's column-major Mat4."""
    return pb.Mat4(m=[float(rows[r][c]) for c in range(4) for r in range(4)])


def instance(mesh: str, translation=(0.0, 0.0, 0.0), linear=None, casts: bool = True,
             receives: bool = True) -> pb.Instance:
    """An uploaded mesh placed by `linear` (3 x 3 rows, default the identity) then moved by
    `translation`."""
    a = linear if linear is not None else ((1, 0, 0), (0, 1, 0), (0, 0, 1))
    rows = [list(a[r]) + [translation[r]] for r in range(3)] + [[0, 0, 0, 1]]
    message = pb.Instance(mesh=mesh, object_to_world=mat4(rows))
    if not casts:
        message.casts = False
    if not receives:
        message.receives = False
    return message


@dataclasses.dataclass
class Frame:
    number: int
    plan: pb.PlanResponse
    images: list  # (MapImage, numpy array): float32 (height, width) or (height, width, 2)
    timings: dict  # stage -> seconds: plan, passes, encode, transfer
    skipped: list  # frames the server skipped since the last frame returned
    streamed_bytes: int  # map bytes as they came over the wire
    error: Optional[tuple] = None  # (grpc.StatusCode, message) when the server refused the frame
    # A session opened with a view (SessionOpen.view): View's answer but the mask and the plan
    # (evaluation, preview, maps, lixels, View's own stage times).
    view: Optional[pb.ViewResponse] = None

    @property
    def mask(self) -> Optional[np.ndarray]:
        """The frame's view mask (float32 (height, width), lit fraction, -1 where no surface),
        when the session was opened with a view."""
        for meta, texels in self.images:
            if getattr(meta, "pass") == pb.PASS_MASK:
                return texels
        return None


class Session:
    """One Session stream. `send` may run ahead of iteration (pipelining); iterating yields each
    served or refused frame in order and ends when the server ends the stream after `close`.
    A stream the server ends with an error raises grpc.RpcError (NOT_FOUND when the scene was
    evicted: upload it again and open a new session)."""

    def __init__(self, stub: pb_grpc.ShadowStub, open_message: pb.SessionOpen, metadata=(),
                 timeout: Optional[float] = None) -> None:
        self._requests: "queue.Queue[Optional[pb.SessionRequest]]" = queue.Queue()
        self._requests.put(pb.SessionRequest(open=open_message))
        self._responses = stub.Session(self._outgoing(), metadata=metadata, timeout=timeout)
        self._coding = open_message.encoding.codec != pb.MAP_CODEC_RAW
        self._held: dict[int, lixel_maps.IntegerImage] = {}
        self.refusals: list[str] = []

    def _outgoing(self) -> Iterator[pb.SessionRequest]:
        while True:
            request = self._requests.get()
            if request is None:
                return
            yield request

    def send(self, number: int, camera: Optional[pb.Camera] = None,
             light: Optional[pb.Light] = None,
             instances: Optional[Iterable[pb.Instance]] = None) -> None:
        """Queues frame `number` (numbers must grow) with what changed since the last frame."""
        frame = pb.SessionFrame(number=number)
        if camera is not None:
            frame.camera.CopyFrom(camera)
        if light is not None:
            frame.light.CopyFrom(light)
        if instances is not None:
            frame.instances.SetInParent()
            frame.instances.instances.extend(instances)
        self._requests.put(pb.SessionRequest(frame=frame))

    def close(self) -> None:
        """Sends no more frames; iteration ends once the server has answered those sent."""
        self._requests.put(None)

    def __iter__(self) -> "Session":
        return self

    def __next__(self) -> Frame:
        skipped: list[int] = []
        header = None
        parts: list[bytearray] = []
        number = None
        streamed = 0
        for response in self._responses:
            which = response.WhichOneof("part")
            if which == "notice":
                skipped.extend(response.notice.skipped)
                if response.notice.code != 0:
                    self.refusals.append(response.notice.message)
                continue
            if number is None:
                number = response.frame
            elif response.frame != number:
                raise ValueError(f"frame {response.frame} began before frame {number} was done")
            if which == "header":
                header = response.header
                parts = [bytearray() for _ in header.images]
            elif which == "chunk":
                chunk = response.chunk
                data = parts[chunk.image_index]
                if chunk.offset != len(data):
                    raise ValueError(f"frame {number}: chunk at {chunk.offset} out of order")
                data.extend(chunk.data)
                streamed += len(chunk.data)
            elif which == "done":
                done = response.done
                timings = {t.stage: t.seconds for t in done.timings}
                if done.code != 0:
                    return Frame(number, pb.PlanResponse(), [], timings, skipped, streamed,
                                 (_status(done.code), done.message))
                return Frame(number, header.plan, self._decode(header, parts), timings, skipped,
                             streamed, None, done.view if done.HasField("view") else None)
        raise StopIteration

    def _decode(self, header: pb.RenderHeader, parts: list[bytearray]) -> list:
        images = []
        held: dict[int, lixel_maps.IntegerImage] = {}
        for meta, data in zip(header.images, parts):
            if meta.coded:
                decoded = lixel_maps.decode(bytes(data), self._held)
                held[decoded.header.frame_id] = decoded.values
                images.append((meta, decoded.texels))
                continue
            channels = 2 if getattr(meta, "pass") == pb.PASS_SILHOUETTE_MAP else 1
            texels = np.frombuffer(bytes(data), dtype=np.float32)
            shape = (meta.height, meta.width) + ((2,) if channels == 2 else ())
            images.append((meta, texels.reshape(shape)))
        if self._coding:
            self._held = held  # the server codes the next frame against this one
        return images


def _status(code: int) -> grpc.StatusCode:
    for status in grpc.StatusCode:
        if status.value[0] == code:
            return status
    return grpc.StatusCode.UNKNOWN
