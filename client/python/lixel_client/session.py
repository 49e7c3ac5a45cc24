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


# Sides of an image at most (the codec's kMaxSide), and the receive bound's default: 1 GiB of
# float32 images a frame, the server's max_response_bytes.
MAX_SIDE = 16385
DEFAULT_MAX_RECEIVE_BYTES = 1 << 30


class StreamError(Exception):
    """A malformed Session stream (a broken or hostile server), naming the part it got wrong
    ("images[2]: chunk at 8192 runs past the image's 4096 bytes"); nothing of the frame is
    returned and no allocation was sized by it past max_receive_bytes."""


def _raw_bytes(meta: pb.MapImage) -> int:
    return meta.width * meta.height * (8 if getattr(meta, "pass") == pb.PASS_SILHOUETTE_MAP else 4)


def _check_header(header: pb.RenderHeader, coding: bool, limit: int) -> None:
    """Every image's shape within the codec's sides, raw sizes their shapes', coded images only
    when asked for, and the float32 total within `limit`: checked before anything is kept."""
    announced = 0
    for i, meta in enumerate(header.images):
        field = f"images[{i}]: "
        if not (1 <= meta.width <= MAX_SIDE and 1 <= meta.height <= MAX_SIDE):
            raise StreamError(f"{field}{meta.width} x {meta.height} is outside [1, {MAX_SIDE}]²")
        if meta.coded and not coding:
            raise StreamError(field + "coded, but no encoding was asked for")
        if not meta.coded and meta.bytes != _raw_bytes(meta):
            raise StreamError(f"{field}{meta.bytes} bytes announced for {meta.width} x "
                              f"{meta.height}, which has {_raw_bytes(meta)}")
        announced += _raw_bytes(meta)
    if announced > limit:
        raise StreamError(f"header: {announced} bytes of maps announced, over max_receive_bytes "
                          f"= {limit}")


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
    evicted: upload it again and open a new session); a malformed one raises StreamError naming
    the part, after at most `max_receive_bytes` of a frame's images were taken in."""

    def __init__(self, stub: pb_grpc.ShadowStub, open_message: pb.SessionOpen, metadata=(),
                 timeout: Optional[float] = None,
                 max_receive_bytes: int = DEFAULT_MAX_RECEIVE_BYTES) -> None:
        self._limit = max_receive_bytes
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
                raise StreamError(f"frame {response.frame} began before frame {number} was done")
            if which == "header":
                if header is not None:
                    raise StreamError(f"frame {number}: header: a second header in one frame")
                try:
                    _check_header(response.header, self._coding, self._limit)
                except StreamError as error:
                    raise StreamError(f"frame {number}: {error}") from None
                header = response.header
                parts = [bytearray() for _ in header.images]
            elif which == "chunk":
                chunk = response.chunk
                if header is None:
                    raise StreamError(f"frame {number}: chunk: before the frame's header")
                if chunk.image_index >= len(parts):
                    raise StreamError(f"frame {number}: chunk: image_index {chunk.image_index} "
                                      "names no image of the header")
                meta = header.images[chunk.image_index]
                data = parts[chunk.image_index]
                # A coded image within the codec's bound on it (codec::MaxCodedBytes).
                raw = _raw_bytes(meta)
                bound = raw + raw // 32 + 8192 if meta.coded else raw
                if chunk.offset != len(data) or len(data) + len(chunk.data) > bound:
                    raise StreamError(f"frame {number}: images[{chunk.image_index}]: chunk at "
                                      f"{chunk.offset} is out of order or runs past the image's "
                                      f"{bound} bytes")
                data.extend(chunk.data)
                streamed += len(chunk.data)
            elif which == "done":
                done = response.done
                timings = {t.stage: t.seconds for t in done.timings}
                if done.code != 0:
                    return Frame(number, pb.PlanResponse(), [], timings, skipped, streamed,
                                 (_status(done.code), done.message))
                if header is None:
                    raise StreamError(f"frame {number}: no header before the frame's end")
                for i, (meta, data) in enumerate(zip(header.images, parts)):
                    if not meta.coded and len(data) != meta.bytes:
                        raise StreamError(f"frame {number}: images[{i}]: {len(data)} of its "
                                          f"{meta.bytes} bytes arrived")
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
