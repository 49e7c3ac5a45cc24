"""lixel_maps.coded_map (client/python/lixel_maps): decodes the C++ encoder's seeded samples bit
for bit, texels and integer values, temporal frames only with their reference held, and refuses
what the C++ decoder refuses (every flipped bit and every truncation of the damaged samples),
naming the same field.

    /usr/bin/python3 python_decoder_test.py <samples dir> [<client/python>]

<samples dir> is what lixel_codec_samples (tests/codec/codec_samples.cc) wrote. Prints each
failure and a closing "N passed, M failed"; exits 1 on any failure.
"""

from __future__ import annotations

import collections
import dataclasses
import json
import pathlib
import struct
import sys
import time
import traceback
import zlib
from typing import Callable

import numpy as np
import zstandard

_HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, sys.argv[2] if len(sys.argv) > 2 else str(_HERE.parents[1] / "client/python"))

import lixel_maps  # noqa: E402
from lixel_maps import CodedMapError, TileMode  # noqa: E402

_HEADER = struct.Struct("<4sBBBBIIHBBIdQQQQQII")


class Failure(Exception):
    pass


def expect(condition: bool, what: str) -> None:
    if not condition:
        raise Failure(what)


def refused(call: Callable[[], object], field: str | None = None) -> CodedMapError:
    """The CodedMapError `call` raises (naming `field` when given); anything else fails."""
    try:
        call()
    except CodedMapError as e:
        expect(field is None or e.field == field, f"refused as {e}, expected field {field}")
        expect(str(e) == f"{e.field}: {e.reason}", f"str() is {str(e)!r}")
        return e
    raise Failure(f"accepted, expected a refusal naming {field}")


def verdict(data: bytes, held: dict[int, lixel_maps.IntegerImage]) -> str:
    try:
        lixel_maps.decode(data, held)
    except CodedMapError as e:
        return e.field
    return "ok"


def header_fields(data: bytes) -> list:
    return list(_HEADER.unpack_from(data, 0))


def with_header(fields: list, payload: bytes) -> bytes:
    """A coded map with these header fields (CRC-32 recomputed) and payload."""
    head = bytearray(_HEADER.pack(*fields))
    struct.pack_into("<I", head, 76, zlib.crc32(bytes(head[:76])))
    return bytes(head) + payload


def recoded(data: bytes, raw: bytes, checksum: bool = True, content_size: bool = True,
            tail: bytes = b"", **changes: int) -> bytes:
    """`data` with its zstd content replaced by `raw` and header fields changed, every size and
    the CRC-32 kept consistent: what a buggy or hostile encoder could send."""
    names = ["magic", "version", "content", "codec", "bits", "width", "height", "tile",
             "max_shift", "reserved_a", "exceptions", "error_bound", "frame_id", "reference_id",
             "keyframe_id", "payload_bytes", "raw_bytes", "reserved_b", "crc"]
    fields = dict(zip(names, header_fields(data)))
    fields.update(changes)
    payload = zstandard.ZstdCompressor(write_checksum=checksum,
                                       write_content_size=content_size).compress(raw) + tail
    fields["payload_bytes"] = len(payload)
    fields["raw_bytes"] = len(raw)
    return with_header([fields[n] for n in names], payload)


def raw_of(data: bytes) -> bytes:
    return zstandard.ZstdDecompressor().decompress(data[80:])


@dataclasses.dataclass
class Sample:
    case: dict
    data: bytes
    texels: np.ndarray  # uint32 bits of the C++ decoder's float32 texels
    values: np.ndarray  # the C++ decoder's integer values


class Suite:
    def __init__(self, directory: pathlib.Path) -> None:
        self.dir = directory
        self.passed = 0
        self.failed = 0
        self.samples: list[Sample] = []
        for line in (directory / "manifest.jsonl").read_text().splitlines():
            case = json.loads(line)
            stem = directory / f"case_{case['case']}"
            self.samples.append(Sample(case, (stem.with_suffix(".lxmc")).read_bytes(),
                                       np.fromfile(stem.with_suffix(".f32"), dtype="<u4"),
                                       np.fromfile(stem.with_suffix(".u32"), dtype="<u4")))
        self.decoded: dict[int, lixel_maps.DecodedMap] = {}  # by case

    def check(self, name: str, test: Callable[[], None]) -> None:
        try:
            test()
        except Failure as e:
            self.failed += 1
            print(f"FAILED {name}: {e}")
        except Exception:  # a crash is a failure of its check, not of the suite
            self.failed += 1
            print(f"FAILED {name}: raised\n{traceback.format_exc()}")
        else:
            self.passed += 1

    def held_for(self, sample: Sample) -> dict[int, lixel_maps.IntegerImage]:
        """The reference a client holds for `sample`: what this decoder made of it."""
        r = sample.case["reference"]
        if r is None:
            return {}
        values = self.decoded[r].values
        return {values.frame_id: values}

    # Every sample decodes to the C++ decoder's texels and values, bit for bit.
    def decodes_like_cpp(self, s: Sample) -> None:
        c = s.case
        d = lixel_maps.decode(s.data, self.held_for(s))
        self.decoded[c["case"]] = d
        channels = 2 if c["content"] == "points" else 1
        shape = (c["height"], c["width"]) + ((2,) if channels == 2 else ())
        expect(d.texels.dtype == np.float32 and d.texels.shape == shape,
               f"texels {d.texels.dtype} {d.texels.shape}, expected float32 {shape}")
        h = d.header
        expect((h.width, h.height, h.bits, h.tile, h.frame_id) ==
               (c["width"], c["height"], c["bits"], c["tile"], c["frame_id"]),
               f"header {h} against the manifest {c}")
        reference = c["reference"]
        expect(h.reference_id == (0 if reference is None else
                                  self.samples[reference].case["frame_id"]),
               f"reference_id {h.reference_id}")
        bits = d.texels.view(np.uint32).ravel()
        differ = np.flatnonzero(bits != s.texels)
        expect(differ.size == 0, f"{differ.size} texels differ from the C++ decoder's, first "
               f"at {differ[:1]}: {bits[differ[:1]]} against {s.texels[differ[:1]]}")
        v = d.values.values
        expect(v.dtype == np.uint32 and v.shape == (c["height"], c["width"], channels),
               f"values {v.dtype} {v.shape}")
        expect(np.array_equal(v.ravel(), s.values), "values differ from the C++ decoder's")
        temporal = int(np.count_nonzero(d.tile_modes >= TileMode.TEMPORAL))
        expect(temporal == c["temporal_tiles"] and d.tile_modes.size == c["tiles"],
               f"{temporal} temporal tiles of {d.tile_modes.size}, the encoder made "
               f"{c['temporal_tiles']} of {c['tiles']}")

    # A temporal frame decodes only against its own reference.
    def temporal_needs_its_reference(self, s: Sample) -> None:
        e = refused(lambda: lixel_maps.decode(s.data), "coded_map.reference_id")
        expect("not held" in e.reason, e.reason)
        h = lixel_maps.read_header(s.data)
        refused(lambda: lixel_maps.decode(s.data, {h.reference_id + 1: self.decoded[
            s.case["reference"]].values}), "coded_map.reference_id")
        held = self.held_for(s)
        reference = held[h.reference_id]
        other_bits = dataclasses.replace(reference, bits=23 if reference.bits != 23 else 22)
        refused(lambda: lixel_maps.decode(s.data, {h.reference_id: other_bits}),
                "coded_map.reference_id")
        short = dataclasses.replace(reference, values=reference.values.ravel()[:-1])
        refused(lambda: lixel_maps.decode(s.data, {h.reference_id: short}),
                "coded_map.reference_id")
        # Another frame of the same shape under the reference's id: refused where an
        # exception's texel no longer holds 0 or a shifted tile's value passes 2^(N - shift),
        # else decoded (the ids are the client's promise), but not to these texels.
        others = [t for t in self.samples if t.case["case"] != s.case["reference"] and
                  t.case["reference"] is None and
                  all(t.case[k] == s.case[k] for k in ("content", "codec", "bits", "width",
                                                        "height"))]
        for other in others:
            wrong = dataclasses.replace(self.decoded[other.case["case"]].values,
                                        frame_id=h.reference_id)
            try:
                d = lixel_maps.decode(s.data, {h.reference_id: wrong})
            except lixel_maps.CodedMapError as e:
                expect(e.field in ("coded_map.exceptions", "coded_map.payload"),
                       f"refused as {e}")
                continue
            expect(not np.array_equal(d.values.values.ravel(), s.values),
                   "decoded the same values against another reference")

    # Every flipped bit and every truncation: the C++ decoder's verdict, field for field; a flip
    # both accept decodes to the undamaged values.
    def damage_like_cpp(self, s: Sample) -> None:
        held = self.held_for(s)
        good = self.decoded[s.case["case"]].values.values
        stem = self.dir / f"case_{s.case['case']}"
        mismatches = []
        flipped = bytearray(s.data)
        for line in stem.with_suffix(".flips").read_text().splitlines():
            byte, bit, cpp = line.split()
            byte, bit = int(byte), int(bit)
            flipped[byte] ^= 1 << bit
            ours = verdict(bytes(flipped), held)
            if ours == "ok":
                d = lixel_maps.decode(bytes(flipped), held)
                if not np.array_equal(d.values.values, good):
                    ours = "ok, but other values"
            flipped[byte] ^= 1 << bit
            if ours != cpp:
                mismatches.append(f"byte {byte} bit {bit}: {ours}, C++ {cpp}")
        for line in stem.with_suffix(".cuts").read_text().splitlines():
            n, cpp = line.split()
            ours = verdict(s.data[:int(n)], held)
            if ours != cpp:
                mismatches.append(f"first {n} bytes: {ours}, C++ {cpp}")
        expect(not mismatches, f"{len(mismatches)} verdicts differ: {mismatches[:5]}")

    def every_tile_mode_occurs(self) -> None:
        seen = collections.Counter()
        for d in self.decoded.values():
            seen.update(int(m) for m in d.tile_modes)
        expect(all(seen[m] > 0 for m in TileMode), f"tile modes seen: {dict(seen)}")

    def every_tile_shift_occurs(self) -> None:
        seen = collections.Counter()
        for d in self.decoded.values():
            seen.update(zip((int(m) for m in d.tile_modes), (int(t) for t in d.tile_shifts)))
        shifts = {t for _, t in seen}
        expect(shifts == set(range(lixel_maps.MAX_TILE_SHIFT + 1)), f"shifts seen: {shifts}")
        shifted_modes = {m for m, t in seen if t > 0}
        expect(shifted_modes == {int(m) for m in TileMode}, f"modes of shifted tiles seen: "
               f"{shifted_modes}")

    def shifted_tile_refusals(self) -> None:
        """One 8 x 8 tile of N = 16 and shift 8, its first residual c and the rest 0: c up to
        2^(16 - 8) decodes (256 is d = 1), past it the map is refused, as is a tile shift past the
        header's max_shift, a max_shift above the tiles' largest and one no codec allows."""
        def coded(c: int, tile_shift: int = 8, max_shift: int = 8, codec: int = 1,
                  bits: int = 16) -> bytes:
            z = np.zeros(64, dtype=np.uint32)
            z[0] = 2 * c
            raw = bytes([tile_shift << 4]) + b"".join(
                ((z >> np.uint32(8 * b)) & np.uint32(255)).astype(np.uint8).tobytes()
                for b in range((bits + 7) // 8))
            payload = zstandard.ZstdCompressor(write_checksum=True,
                                               write_content_size=True).compress(raw)
            bound = lixel_maps.quantised_error_bound(16, max_shift) if codec == 1 else 0.0
            return with_header([b"LXMC", lixel_maps.FORMAT_VERSION, 1, codec, bits, 8, 8, 8,
                                max_shift, 0, 0, bound, 5, 0, 5, len(payload), len(raw), 0, 0],
                               payload)
        top = lixel_maps.decode(coded(256))
        expect(top.texels[0, 0] == 1.0 and top.values.values[0, 0, 0] == 0xFFFF,
               f"c = 2^(N - s) decodes to {top.texels[0, 0]}")
        expect(top.tile_shifts.tolist() == [8], f"tile shifts {top.tile_shifts}")
        refused(lambda: lixel_maps.decode(coded(257)), "coded_map.payload")
        refused(lambda: lixel_maps.decode(coded(1, tile_shift=3, max_shift=2)),
                "coded_map.tile_modes")
        refused(lambda: lixel_maps.decode(coded(1, max_shift=9)), "coded_map.max_shift")
        # A header stating more than its tiles' largest shift: a second coding of the same map.
        refused(lambda: lixel_maps.decode(coded(1, tile_shift=2, max_shift=3)),
                "coded_map.max_shift")
        refused(lambda: lixel_maps.decode(coded(1, tile_shift=0, max_shift=1, codec=2, bits=32)),
                "coded_map.max_shift")

    def refusals(self) -> None:
        by_kind = {}
        for s in self.samples:
            c = s.case
            key = (c["codec"], c["reference"] is not None, c["width"] * c["height"] >= 60000)
            by_kind.setdefault(key, s)
        big = by_kind[("quantised", False, True)]
        data = big.data
        # Truncated, padded, empty, not a coded map.
        refused(lambda: lixel_maps.decode(data[:-1]), "coded_map.payload_bytes")
        refused(lambda: lixel_maps.decode(data[:79]), "coded_map.header")
        refused(lambda: lixel_maps.decode(b""), "coded_map.header")
        refused(lambda: lixel_maps.decode(data + b"\0\0\0"), "coded_map.payload_bytes")
        refused(lambda: lixel_maps.decode(b"x" * 200), "coded_map.magic")
        # One flipped bit in the header: its CRC-32.
        flipped = bytearray(data)
        flipped[9] ^= 0x10
        refused(lambda: lixel_maps.decode(bytes(flipped)), "coded_map.header")
        refused(lambda: lixel_maps.read_header(bytes(flipped)), "coded_map.header")
        # A flipped byte in the payload: zstd's checksum (the last 4 bytes) or its decoding.
        for at, why in ((80 + (len(data) - 80) // 2, "zstd"), (len(data) - 2, "checksum")):
            flipped = bytearray(data)
            flipped[at] ^= 0xFF
            e = refused(lambda: lixel_maps.decode(bytes(flipped)), "coded_map.payload")
            expect(why in e.reason, e.reason)
        # A header claiming a huge image: refused by the texel budget before anything is read.
        fields = header_fields(data)
        # width, height, tile, max_shift, reserved, exceptions
        fields[5:11] = [16385, 16385, 64, 0, 0, 0]
        fields[15:17] = [10, 1000000]  # payload_bytes, raw_bytes
        huge = with_header(fields, b"\0" * 10)
        refused(lambda: lixel_maps.decode(huge, max_texels=1 << 20), "coded_map.width")
        fields[5:7] = [4, 4]
        fields[16] = 1 << 40
        refused(lambda: lixel_maps.decode(with_header(fields, b"\0" * 10)), "coded_map.raw_bytes")
        fields[16] = 1 + 2 * 16
        fields[11] = 1e-3
        refused(lambda: lixel_maps.decode(with_header(fields, b"\0" * 10)),
                "coded_map.error_bound")
        exact = header_fields(by_kind[("exact", False, True)].data)
        exact[11] = 0.0
        exact[10] = 1
        refused(lambda: lixel_maps.decode(with_header(exact, b"")), "coded_map.exceptions")
        # What a buggy or hostile encoder could send, each size and the CRC kept consistent.
        raw = raw_of(data)
        expect(np.array_equal(lixel_maps.decode(recoded(data, raw)).texels.view(np.uint32)
                              .ravel(), big.texels), "a recoded copy decodes otherwise")
        refused(lambda: lixel_maps.decode(recoded(data, raw, checksum=False)), "coded_map.payload")
        refused(lambda: lixel_maps.decode(recoded(data, raw, content_size=False)),
                "coded_map.payload")
        for tail in (b"\0", zstandard.ZstdCompressor().compress(b"more")):
            refused(lambda: lixel_maps.decode(recoded(data, raw, tail=tail)), "coded_map.payload")
        refused(lambda: lixel_maps.decode(recoded(data, raw, reserved_a=1)), "coded_map.reserved")
        refused(lambda: lixel_maps.decode(recoded(data, raw, reserved_b=1)), "coded_map.reserved")
        refused(lambda: lixel_maps.decode(recoded(data, raw[:-1])), "coded_map.raw_bytes")
        refused(lambda: lixel_maps.decode(recoded(data, b"\4" + raw[1:])), "coded_map.tile_modes")
        refused(lambda: lixel_maps.decode(recoded(data, b"\2" + raw[1:])), "coded_map.tile_modes")
        h = lixel_maps.read_header(data)
        expect(h.exceptions >= 2, f"{h.exceptions} exceptions")
        tiles = h.tiles_across * h.tiles_up
        records = bytearray(raw)
        first, second = tiles, tiles + 8
        records[first:first + 8], records[second:second + 8] = (raw[second:second + 8],
                                                                raw[first:first + 8])
        refused(lambda: lixel_maps.decode(recoded(data, bytes(records))), "coded_map.exceptions")
        records = bytearray(raw)
        records[second:second + 4] = raw[first:first + 4]
        refused(lambda: lixel_maps.decode(recoded(data, bytes(records))), "coded_map.exceptions")
        records = bytearray(raw)
        struct.pack_into("<I", records, first, h.width * h.height)
        refused(lambda: lixel_maps.decode(recoded(data, bytes(records))), "coded_map.exceptions")
        # Keyframe rules, and a named reference no tile reads.
        refused(lambda: lixel_maps.decode(recoded(data, raw, keyframe_id=h.frame_id + 1)),
                "coded_map.keyframe_id")
        refused(lambda: lixel_maps.decode(recoded(data, raw, frame_id=0)), "coded_map.frame_id")
        held = {7: self.decoded[big.case["case"]].values}
        refused(lambda: lixel_maps.decode(recoded(data, raw, reference_id=7), held),
                "coded_map.reference_id")
        e = refused(lambda: lixel_maps.decode(recoded(data, raw, reference_id=7, keyframe_id=0),
                                              held), "coded_map.keyframe_id")
        expect("names the keyframe it starts at" in e.reason, e.reason)
        e = refused(lambda: lixel_maps.decode(recoded(data, raw, reference_id=h.frame_id), held),
                    "coded_map.reference_id")
        expect("refers to another frame" in e.reason, e.reason)
        # A reference with a value beyond N bits (in a copy tile, or any other): refused before
        # a tile reads it.
        temporal = by_kind[("quantised", True, False)]
        reference = self.held_for(temporal)
        (rid, image), = reference.items()
        temporal_raw = raw_of(temporal.data)
        refused(lambda: lixel_maps.decode(recoded(temporal.data, temporal_raw + b"\0"),
                                          reference), "coded_map.raw_bytes")
        signed = dataclasses.replace(image, values=image.values.astype(np.int64))
        refused(lambda: lixel_maps.decode(temporal.data, {rid: signed}), "coded_map.reference_id")
        modes = self.decoded[temporal.case["case"]].tile_modes
        t = int(np.flatnonzero(modes == TileMode.COPY)[0])
        tile = lixel_maps.read_header(temporal.data).tile
        across = -(-image.width // tile)
        wide = image.values.copy()
        wide[(t // across) * tile, (t % across) * tile, 0] = 1 << 24
        refused(lambda: lixel_maps.decode(temporal.data, {rid: dataclasses.replace(
            image, values=wide)}), "coded_map.reference_id")
        # Any bytes-like input.
        d = lixel_maps.decode(bytearray(data))
        expect(np.array_equal(d.texels.view(np.uint32).ravel(), big.texels), "bytearray input")

    def run(self) -> int:
        for s in self.samples:
            self.check(f"case {s.case['case']} decodes like C++",
                       lambda s=s: self.decodes_like_cpp(s))
        for s in self.samples:
            if s.case["case"] not in self.decoded:
                continue
            if s.case["reference"] is not None:
                self.check(f"case {s.case['case']} needs its reference",
                           lambda s=s: self.temporal_needs_its_reference(s))
            if s.case["damaged"]:
                self.check(f"case {s.case['case']} damaged like C++",
                           lambda s=s: self.damage_like_cpp(s))
        self.check("every tile mode occurs", self.every_tile_mode_occurs)
        self.check("every tile shift occurs", self.every_tile_shift_occurs)
        self.check("shifted tiles' refusals", self.shifted_tile_refusals)
        self.check("refusals", self.refusals)
        self.check("a 300 x 200 map decodes in under a second", self.fast_enough)
        print(f"{self.passed} passed, {self.failed} failed")
        return 1 if self.failed or not self.samples else 0

    def fast_enough(self) -> None:
        # Vectorised decoding: a loop over texels in Python takes seconds at this size.
        for s in self.samples:
            if s.case["width"] * s.case["height"] >= 60000:
                start = time.perf_counter()
                lixel_maps.decode(s.data, self.held_for(s))
                seconds = time.perf_counter() - start
                expect(seconds < 1.0, f"case {s.case['case']} took {seconds:.2f} s")


def main() -> int:
    if len(sys.argv) not in (2, 3):
        print(__doc__)
        return 2
    return Suite(pathlib.Path(sys.argv[1])).run()


if __name__ == "__main__":
    sys.exit(main())
