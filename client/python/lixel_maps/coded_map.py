"""Decodes lixel's coded maps (docs/service.md, "Coded maps", "The format"), refusing what the C++
decoder (codec/src/map_decoder.cc) refuses, with the same field names: every size is checked
against the header and the caller's budget before anything is allocated, the header carries a
CRC-32 and the payload zstd's content checksum, and a frame whose reference is not held is
refused, never decoded against another frame.

    import lixel_maps
    held = {}
    decoded = lixel_maps.decode(coded_bytes, held)
    held[decoded.header.frame_id] = decoded.values  # what the next frame's temporal tiles read
    depth = decoded.texels  # float32, (height, width); row 0 is the map's bottom row

Numpy and Debian's python3-zstandard only.
"""

from __future__ import annotations

import dataclasses
import enum
import math
import struct
import zlib

import numpy as np
import zstandard

HEADER_BYTES = 80
FORMAT_VERSION = 2  # version 2 added the tiles' shifts
MIN_QUANTISED_BITS = 16
MAX_QUANTISED_BITS = 24
MIN_TILE = 8
MAX_TILE = 1024
MAX_TILE_SHIFT = 8  # the coarsest step a quantised tile may take, 2^8 of N's
MAX_SIDE = 16385  # a 16384² map's corner depth
DEFAULT_MAX_TEXELS = 16385 * 16385 * 2

_MAGIC = b"LXMC"
# magic, version, content, codec, bits, width, height, tile, max_shift, reserved, exceptions,
# error_bound, frame_id, reference_id, keyframe_id, payload_bytes, raw_bytes, reserved, crc32.
_HEADER = struct.Struct("<4sBBBBIIHBBIdQQQQQII")
_CRC_OFFSET = 76
_ZSTD_MAGIC = 0xFD2FB528
# zstd's largest window on 64-bit targets. The frame states its content size, which the header
# bounds, and zstd never buffers more than that, so the window limit guards nothing here; the C++
# decoder (one-shot ZSTD_decompressDCtx) applies none either.
_ZSTD_MAX_WINDOW = 1 << 31


class Content(enum.IntEnum):
    DEPTH = 1  # one float32 per texel: stored depth d (1 at the light's near end, 0 cleared)
    POINTS = 2  # two float32 per texel (RG): silhouette points, (-1, -1) where none


class Codec(enum.IntEnum):
    QUANTISED = 1  # depth only: q = round(d (2^N - 1)), exceptions with their exact bits
    EXACT = 2  # the float32 bit pattern of every channel (N = 32)


class TileMode(enum.IntEnum):
    """A tile byte's low four bits; its high four are the tile's shift."""

    GRADIENT = 0  # a + b - c
    MED = 1  # LOCO-I's median edge detector
    TEMPORAL = 2  # the reference frame's value at the same texel
    COPY = 3  # every texel equals the reference frame's: no residuals


class CodedMapError(ValueError):
    """A refused coded map. `field` names the header field as the C++ decoder's Error.field does
    ("coded_map.reference_id"); `reason` says what is wrong with it."""

    def __init__(self, field: str, reason: str) -> None:
        super().__init__(f"{field}: {reason}")
        self.field = field
        self.reason = reason

    def __str__(self) -> str:
        return f"{self.field}: {self.reason}"


def _bad(field: str, reason: str) -> CodedMapError:
    return CodedMapError("coded_map." + field, reason)


@dataclasses.dataclass(frozen=True)
class CodedHeader:
    """The fixed 80-byte header every coded map starts with."""

    content: Content
    codec: Codec
    bits: int  # N: [16, 24] quantised, 32 exact
    width: int  # texels, [1, MAX_SIDE]
    height: int  # texels, [1, MAX_SIDE]
    tile: int  # tile side, texels, [MIN_TILE, MAX_TILE]
    max_shift: int  # the largest tile shift, [0, MAX_TILE_SHIFT]; 0 exact
    exceptions: int  # texels stored with exact float32 bits (quantised only)
    error_bound: float  # max |decoded - float| over texels in [0, 1] (N's at max_shift); 0 exact
    frame_id: int  # this image's id, non-zero
    reference_id: int  # the image its temporal tiles read; 0: none (a keyframe)
    keyframe_id: int  # the keyframe its chain of references starts at
    payload_bytes: int  # the zstd frame that follows the header
    raw_bytes: int  # that frame's content size

    @property
    def channels(self) -> int:
        return 2 if self.content == Content.POINTS else 1

    @property
    def texels(self) -> int:
        return self.width * self.height

    @property
    def tiles_across(self) -> int:
        return (self.width + self.tile - 1) // self.tile

    @property
    def tiles_up(self) -> int:
        return (self.height + self.tile - 1) // self.tile


@dataclasses.dataclass
class IntegerImage:
    """An image's values as the predictors see them: N-bit integers (quantised) or float32 bits
    (exact). A decoder keeps these for the next frame's temporal tiles."""

    content: Content
    codec: Codec
    bits: int
    width: int
    height: int
    frame_id: int
    keyframe_id: int
    values: np.ndarray  # uint32, (height, width, channels), row 0 at the bottom

    @property
    def channels(self) -> int:
        return 2 if self.content == Content.POINTS else 1

    def matches(self, h: CodedHeader) -> bool:
        """Whether `h`'s temporal tiles may read this image."""
        return (self.content == h.content and self.codec == h.codec and self.bits == h.bits
                and self.width == h.width and self.height == h.height)


@dataclasses.dataclass
class DecodedMap:
    header: CodedHeader
    # float32, (height, width) for depth, (height, width, 2) for points; row 0 the bottom row.
    # Quantised depth lies within header.error_bound of what the encoder was given.
    texels: np.ndarray
    values: IntegerImage  # what a later frame's temporal tiles read
    tile_modes: np.ndarray  # uint8 TileMode per tile, rows of tiles from the bottom
    # uint8 shift per tile: a tile of shift s lies within quantised_error_bound(N, s)
    tile_shifts: np.ndarray


def quantised_error_bound(bits: int, shift: int = 0) -> float:
    """Half a tile's quantisation step (2^shift of N's) plus the float32 rounding of the decoded
    value (2^-25); the same double operations as the C++ QuantisedErrorBound, so the header's
    value (at its max_shift) compares equal."""
    return math.ldexp(0.5, shift) / (2.0 ** bits - 1.0) + 2.0 ** -25


def read_header(data: bytes) -> CodedHeader:
    """Reads and checks the header at the start of `data`: magic, version, CRC-32, every field's
    range and their consistency, and that exactly payload_bytes follow it."""
    if len(data) < HEADER_BYTES:
        raise _bad("header", f"{len(data)} bytes, shorter than the {HEADER_BYTES}-byte header")
    (magic, version, content, codec, bits, width, height, tile, max_shift, reserved_a, exceptions,
     error_bound, frame_id, reference_id, keyframe_id, payload_bytes, raw_bytes, reserved_b,
     crc) = _HEADER.unpack_from(data, 0)
    if magic != _MAGIC:
        raise _bad("magic", 'not "LXMC": not a coded map')
    if version != FORMAT_VERSION:
        raise _bad("version", f"{version}, this decoder reads version {FORMAT_VERSION}")
    if crc != zlib.crc32(bytes(data[:_CRC_OFFSET])):
        raise _bad("header", "CRC-32 mismatch: the header is corrupt")
    if content not in (1, 2):
        raise _bad("content", f"{content} is not 1 or 2")
    if codec not in (1, 2):
        raise _bad("codec", f"{codec} is not 1 or 2")
    if codec == Codec.QUANTISED:
        if content != Content.DEPTH:
            raise _bad("codec", "quantised codes depth only")
        if not MIN_QUANTISED_BITS <= bits <= MAX_QUANTISED_BITS:
            raise _bad("bits", f"{bits} is outside [16, 24]")
    elif bits != 32:
        raise _bad("bits", f"{bits}: the exact codec has 32")
    if not 1 <= width <= MAX_SIDE:
        raise _bad("width", f"{width} is outside [1, 16385]")
    if not 1 <= height <= MAX_SIDE:
        raise _bad("height", f"{height} is outside [1, 16385]")
    if not MIN_TILE <= tile <= MAX_TILE:
        raise _bad("tile", f"{tile} is outside [8, 1024]")
    most_shift = MAX_TILE_SHIFT if codec == Codec.QUANTISED else 0
    if max_shift > most_shift:
        raise _bad("max_shift", f"{max_shift} is outside [0, "
                   f"{'8' if most_shift else '0: the exact codec'}]")
    if reserved_a != 0 or reserved_b != 0:
        raise _bad("reserved", "bytes 19 and 72-75 must be zero")
    texels = width * height
    if exceptions > texels:
        raise _bad("exceptions", f"{exceptions}, more than the {texels} texels")
    if codec == Codec.EXACT and exceptions != 0:
        raise _bad("exceptions", "the exact codec has none")
    bound = quantised_error_bound(bits, max_shift) if codec == Codec.QUANTISED else 0.0
    # Bit for bit: -0 is not the exact codec's 0, nor a NaN any bound.
    if struct.pack("<d", error_bound) != struct.pack("<d", bound):
        raise _bad("error_bound", "not the bound its N and max_shift state")
    if frame_id == 0:
        raise _bad("frame_id", "0 names no frame")
    if reference_id == 0 and keyframe_id != frame_id:
        raise _bad("keyframe_id", "a keyframe (no reference) is its own keyframe")
    if reference_id != 0 and keyframe_id == 0:
        raise _bad("keyframe_id", "0: a frame with a reference names the keyframe it starts at")
    if reference_id != 0 and reference_id == frame_id:
        raise _bad("reference_id", "the frame's own id: a frame refers to another frame")
    follow = len(data) - HEADER_BYTES
    if payload_bytes != follow:
        raise _bad("payload_bytes", f"{payload_bytes} stated, {follow} follow the header "
                   "(truncated or padded)")
    h = CodedHeader(Content(content), Codec(codec), bits, width, height, tile, max_shift, exceptions,
                    error_bound, frame_id, reference_id, keyframe_id, payload_bytes, raw_bytes)
    # The largest payload the header allows: tile modes, exceptions, every residual.
    tiles = h.tiles_across * h.tiles_up
    most = tiles + 8 * exceptions + _byte_planes(bits) * texels * h.channels
    if not tiles <= raw_bytes <= most:
        raise _bad("raw_bytes", f"{raw_bytes} is outside the [{tiles}, {most}] its size and "
                   "tiles allow")
    return h


def decode(data: bytes, references: dict[int, IntegerImage] | None = None,
           max_texels: int = DEFAULT_MAX_TEXELS) -> DecodedMap:
    """Decodes one coded map. A frame with a reference reads it from `references` (by frame id);
    one that is absent or of another shape is refused naming coded_map.reference_id.
    `max_texels`: the most texels (times channels) one image may hold; larger ones are refused
    before any allocation. Raises CodedMapError."""
    if not isinstance(data, bytes):
        data = bytes(data)
    h = read_header(data)
    channels = h.channels
    count = h.texels * channels
    if count > max_texels:
        raise _bad("width", f"{h.width} x {h.height} x {channels} values, over the decoder's "
                   f"{max_texels}")
    reference = _reference_of(h, references or {})
    payload = memoryview(data)[HEADER_BYTES:]
    _check_frame(h, payload)
    try:
        raw = zstandard.ZstdDecompressor(max_window_size=_ZSTD_MAX_WINDOW).decompress(payload)
    except zstandard.ZstdError as e:
        raise _bad("payload", f"zstd: {e}") from None
    if len(raw) != h.raw_bytes:
        raise _bad("payload", "decompressed size is not raw_bytes")

    across, up = h.tiles_across, h.tiles_up
    tiles = across * up
    tile_bytes = np.frombuffer(raw, dtype=np.uint8, count=tiles)
    modes = tile_bytes & np.uint8(15)
    shifts = tile_bytes >> np.uint8(4)
    wrong = ((modes > TileMode.COPY) | (shifts > h.max_shift)
             | ((modes >= TileMode.TEMPORAL) & (reference is None)))
    if wrong.any():
        t = int(np.argmax(wrong))
        if modes[t] > TileMode.COPY:
            raise _bad("tile_modes", f"tile {t} has mode {modes[t]}")
        if shifts[t] > h.max_shift:
            raise _bad("tile_modes", f"tile {t} has shift {shifts[t]}, past the header's "
                       f"max_shift {h.max_shift}")
        raise _bad("tile_modes", f"tile {t} reads a reference frame, and none is named")
    # One map, one coding: the header states the largest shift its tiles take, not more.
    largest = int(shifts.max())
    if largest != h.max_shift:
        raise _bad("max_shift", f"{h.max_shift}, but the largest tile shift is {largest}")
    if h.reference_id != 0 and not (modes >= TileMode.TEMPORAL).any():
        raise _bad("reference_id", "named, but no tile reads it")
    spans_x = [(x0, min(h.width, x0 + h.tile)) for x0 in range(0, h.width, h.tile)]
    spans_y = [(y0, min(h.height, y0 + h.tile)) for y0 in range(0, h.height, h.tile)]
    tile_texels = np.outer([y1 - y0 for y0, y1 in spans_y],
                           [x1 - x0 for x0, x1 in spans_x]).ravel()
    residuals = int(tile_texels[modes != TileMode.COPY].sum(dtype=np.int64)) * channels
    planes = _byte_planes(h.bits)
    need = tiles + 8 * h.exceptions + planes * residuals
    if h.raw_bytes != need:
        raise _bad("raw_bytes", f"{h.raw_bytes} is not what its tiles and exceptions need "
                   f"({need})")

    mask = np.uint32((1 << h.bits) - 1)
    s = _signed_residuals(raw, tiles + 8 * h.exceptions, residuals, planes, mask)
    # The image with a zero row below and a zero column to its left: with those, the gradient
    # and MED rules need no special case at the edges (bottom row p = a, left column p = b,
    # texel (0, 0) p = 0 is what a + b - c and MED give when b = c = 0 or a = c = 0).
    # Arithmetic is in uint32, which wraps modulo 2^32; 2^N divides 2^32, so masking with
    # 2^N - 1 afterwards gives the format's results modulo 2^N.
    padded = np.zeros((h.height + 1, h.width + 1, channels), dtype=np.uint32)
    k = 0
    t = 0
    for y0, y1 in spans_y:
        for x0, x1 in spans_x:
            m = modes[t]
            shift = int(shifts[t])
            t += 1
            inside = (slice(y0 + 1, y1 + 1), slice(x0 + 1, x1 + 1))
            if m == TileMode.COPY:
                padded[inside] = reference[y0:y1, x0:x1]
                continue
            n = (y1 - y0) * (x1 - x0) * channels
            tile_s = s[k:k + n].reshape(y1 - y0, x1 - x0, channels)
            k += n
            if shift > 0:
                _shifted_tile(padded, tile_s, m, reference, x0, x1, y0, y1, shift, h.bits, mask)
            elif m == TileMode.TEMPORAL:
                padded[inside] = (reference[y0:y1, x0:x1] + tile_s) & mask
            elif m == TileMode.GRADIENT:
                _gradient_tile(padded, tile_s, x0, x1, y0, y1, mask)
            else:
                _med_tile(padded, tile_s, x0, x1, y0, y1, mask)
    values = np.ascontiguousarray(padded[1:, 1:])
    del padded

    if h.codec == Codec.EXACT:
        texels = values.view(np.float32).copy()
    else:
        steps = float((1 << h.bits) - 1)
        texels = (values.astype(np.float64) / steps).astype(np.float32)
        _apply_exceptions(texels, values, raw, tiles, h.exceptions, count)
    shape = (h.height, h.width) if channels == 1 else (h.height, h.width, channels)
    image = IntegerImage(h.content, h.codec, h.bits, h.width, h.height, h.frame_id,
                         h.keyframe_id, values)
    return DecodedMap(h, texels.reshape(shape), image, modes, shifts)


def _byte_planes(bits: int) -> int:
    return (bits + 7) // 8


def _reference_of(h: CodedHeader, held: dict[int, IntegerImage]) -> np.ndarray | None:
    if h.reference_id == 0:
        return None
    r = held.get(h.reference_id)
    if r is None:
        raise _bad("reference_id", f"frame {h.reference_id} is not held (its keyframe is "
                   f"{h.keyframe_id}): ask for a keyframe")
    values = np.asarray(r.values)
    if (not r.matches(h) or values.dtype != np.uint32
            or values.size != h.texels * h.channels):
        raise _bad("reference_id", f"frame {h.reference_id} is not of this image's content, "
                   "codec, N and size")
    if h.bits < 32 and (values > np.uint32((1 << h.bits) - 1)).any():
        raise _bad("reference_id", f"frame {h.reference_id} holds values beyond N bits: not a "
                   "decoded frame")
    return values.reshape(h.height, h.width, h.channels)


def _check_frame(h: CodedHeader, payload: memoryview) -> None:
    """One zstd frame, its content size stated and equal to the header's raw_bytes, its checksum
    on (RFC 8878 §3.1.1: the magic number, then the frame header descriptor, whose bit 2 is the
    content checksum flag)."""
    if len(payload) < 5 or int.from_bytes(payload[:4], "little") != _ZSTD_MAGIC:
        raise _bad("payload", "not a zstd frame")
    if payload[4] & 0x04 == 0:
        raise _bad("payload", "its zstd frame carries no checksum")
    try:
        size = zstandard.frame_content_size(payload)
    except zstandard.ZstdError:
        size = -1
    if size != h.raw_bytes:  # -1: not stated
        raise _bad("payload", "its zstd frame does not state the header's raw_bytes")
    if _frame_bytes(payload) != len(payload):
        raise _bad("payload", "not exactly one zstd frame (truncated or followed by bytes)")


def _frame_bytes(payload: memoryview) -> int | None:
    """The first zstd frame's compressed size, as ZSTD_findFrameCompressedSize walks it (header,
    block headers, checksum; RFC 8878 §3.1.1.2), or None where the frame is cut short or has a
    reserved block type. python-zstandard 0.20 does not expose that function."""
    try:
        at = zstandard.frame_header_size(payload)
        zstandard.get_frame_parameters(payload)  # the whole header is there and valid
    except zstandard.ZstdError:
        return None
    size = len(payload)
    while True:
        if size - at < 3:
            return None
        block = payload[at] | payload[at + 1] << 8 | payload[at + 2] << 16
        kind = (block >> 1) & 3
        if kind == 3:
            return None
        body = 1 if kind == 1 else block >> 3  # RLE blocks hold one byte
        if 3 + body > size - at:
            return None
        at += 3 + body
        if block & 1:
            break
    if payload[4] & 0x04:
        if size - at < 4:
            return None
        at += 4
    return at


def _signed_residuals(raw: bytes, offset: int, count: int, planes: int,
                      mask: np.uint32) -> np.ndarray:
    """The residuals s (mod 2^N, as uint32) from their byte planes: z gathered from plane b's
    byte b, then zig-zag undone (z >> 1 for even z, -(z + 1) / 2 = ~(z >> 1) for odd)."""
    z = np.zeros(count, dtype=np.uint32)
    for b in range(planes):
        plane = np.frombuffer(raw, dtype=np.uint8, count=count, offset=offset + b * count)
        z |= plane.astype(np.uint32) << np.uint32(8 * b)
    # Each residual is N bits: larger ones would give one map two codings.
    if count and int(z.max()) > int(mask):
        raise _bad("payload", "a residual beyond N bits")
    return ((z >> np.uint32(1)) ^ (np.uint32(0) - (z & np.uint32(1)))) & mask


def _gradient_tile(padded: np.ndarray, tile_s: np.ndarray, x0: int, x1: int, y0: int, y1: int,
                   mask: np.uint32) -> None:
    """v - a - b + c = s at every texel of the tile, so summing over [x0, x] x [y0, y]
    telescopes: v(x, y) = S(x, y) + v(x0 - 1, y) + v(x, y0 - 1) - v(x0 - 1, y0 - 1), with S the
    2-D prefix sum of s and the neighbours outside the tile rebuilt earlier in the walk (or the
    zero padding outside the image)."""
    around = padded[y0:y1 + 1, x0:x1 + 1]
    v = np.cumsum(tile_s, axis=0, dtype=np.uint32)
    np.cumsum(v, axis=1, dtype=np.uint32, out=v)
    v += around[1:, :1]
    v += around[:1, 1:]
    v -= around[:1, :1]
    v &= mask
    around[1:, 1:] = v


def _med_tile(padded: np.ndarray, tile_s: np.ndarray, x0: int, x1: int, y0: int, y1: int,
              mask: np.uint32) -> None:
    """MED is not linear, so it is rebuilt texel by texel, but a texel reads only its left,
    lower and lower-left neighbours: those with equal x + y (an anti-diagonal) depend only on
    earlier diagonals, and each diagonal is one vectorised step. In the flattened padded image
    a diagonal is a strided slice (x + 1 and y - 1 is a step of width + 1 - 1 = width)."""
    channels = padded.shape[2]
    row = padded.shape[1]  # width + 1
    width = row - 1
    flat = padded.reshape(-1, channels)
    tw, th = x1 - x0, y1 - y0
    s_flat = tile_s.reshape(tw * th, channels)
    s_step = max(tw - 1, 1)  # only used when the diagonal has two texels or more
    for d in range(tw + th - 1):
        i_lo = max(0, d - th + 1)
        i_hi = min(d, tw - 1)
        n = i_hi - i_lo + 1
        # From the diagonal's lower-right texel (x0 + i_hi, y0 + d - i_hi) up and to the left.
        f = (y0 + d - i_hi + 1) * row + x0 + i_hi + 1
        end = f + (n - 1) * width + 1
        a = flat[f - 1:end - 1:width]
        b = flat[f - row:end - row:width]
        c = flat[f - row - 1:end - row - 1:width]
        g = (d - i_hi) * tw + i_hi
        s = s_flat[g:g + (n - 1) * s_step + 1:s_step]
        lo = np.minimum(a, b)
        hi = np.maximum(a, b)
        p = np.where(c >= hi, lo, np.where(c <= lo, hi, (a + b - c) & mask))
        flat[f:end:width] = (p + s) & mask


def _coarse(q: np.ndarray, shift: int) -> np.ndarray:
    """What a tile of shift s reads a value q as: (q + 2^(s-1)) >> s, which inside the tile
    gives back its c."""
    return (q + np.uint32((1 << shift) >> 1)) >> np.uint32(shift)


def _shifted_tile(padded: np.ndarray, tile_s: np.ndarray, mode: TileMode,
                  reference: np.ndarray | None, x0: int, x1: int, y0: int, y1: int, shift: int,
                  bits: int, mask: np.uint32) -> None:
    """A tile of shift s > 0 (depth, one channel): its c's rebuilt by the same predictors over
    its neighbours read coarsened (a local copy of the tile with its left column and lower row,
    those coarsened), refused past 2^(N - s), then stored as min(c 2^s, 2^N - 1)."""
    if mode == TileMode.TEMPORAL:
        c = (_coarse(reference[y0:y1, x0:x1], shift) + tile_s) & mask
    else:
        local = np.zeros((y1 - y0 + 1, x1 - x0 + 1, padded.shape[2]), dtype=np.uint32)
        local[0, :] = _coarse(padded[y0, x0:x1 + 1], shift)
        local[1:, 0] = _coarse(padded[y0 + 1:y1 + 1, x0], shift)
        if mode == TileMode.GRADIENT:
            _gradient_tile(local, tile_s, 0, x1 - x0, 0, y1 - y0, mask)
        else:
            _med_tile(local, tile_s, 0, x1 - x0, 0, y1 - y0, mask)
        c = local[1:, 1:]
    if c.size and int(c.max()) > 1 << (bits - shift):
        raise _bad("payload", "a shifted tile's value past 2^(N - shift): not a coded map")
    padded[y0 + 1:y1 + 1, x0 + 1:x1 + 1] = np.minimum(c << np.uint32(shift), mask)


def _apply_exceptions(texels: np.ndarray, values: np.ndarray, raw: bytes, offset: int,
                      count: int, texel_count: int) -> None:
    """Each exception's texel takes its stored float32 bits; indices strictly increasing and
    inside the image, or the map is refused naming the first one that is not."""
    if count == 0:
        return
    records = np.frombuffer(raw, dtype="<u4", count=2 * count, offset=offset).reshape(count, 2)
    index = records[:, 0]
    wrong = index >= texel_count
    wrong[1:] |= index[1:] <= index[:-1]
    if wrong.any():
        e = int(np.argmax(wrong))
        raise _bad("exceptions", f"exception {e} at texel {index[e]} is out of range or order")
    # An exception's texel holds the integer 0 (what the next frame's temporal tiles read).
    if (values.reshape(-1)[index] != 0).any():
        raise _bad("exceptions", "an exception's texel holds an integer other than 0")
    texels.reshape(-1).view(np.uint32)[index] = records[:, 1]
