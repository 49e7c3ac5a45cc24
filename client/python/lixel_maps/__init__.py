"""lixel's coded maps in Python: a decoder of the format docs/service.md specifies ("Coded maps"),
checked bit for bit against the C++ one (tests/codec/python_decoder_test.py)."""

from lixel_maps.coded_map import (
    FORMAT_VERSION,
    MAX_TILE_SHIFT,
    Codec,
    CodedHeader,
    CodedMapError,
    Content,
    DecodedMap,
    IntegerImage,
    TileMode,
    decode,
    quantised_error_bound,
    read_header,
)

__all__ = [
    "FORMAT_VERSION",
    "MAX_TILE_SHIFT",
    "Codec",
    "CodedHeader",
    "CodedMapError",
    "Content",
    "DecodedMap",
    "IntegerImage",
    "TileMode",
    "decode",
    "quantised_error_bound",
    "read_header",
]
