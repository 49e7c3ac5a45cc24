"""lixel's coded maps in Python: a decoder of the format docs/service.md specifies ("Coded maps"),
checked bit for bit against the C++ one (tests/codec/python_decoder_test.py)."""

from lixel_maps.coded_map import (
    Codec,
    CodedHeader,
    CodedMapError,
    Content,
    DecodedMap,
    IntegerImage,
    TileMode,
    decode,
    read_header,
)

__all__ = [
    "Codec",
    "CodedHeader",
    "CodedMapError",
    "Content",
    "DecodedMap",
    "IntegerImage",
    "TileMode",
    "decode",
    "read_header",
]
