"""Reading a PC2 point cache (clothvk-sim --pc2): the one reader of the scripts and the tests.

    import pc2
    header, samples = pc2.read(path)

header is (magic, version, points, start frame, sample rate, samples); samples a list with one
array('f') of 3 x points floats (x, y, z of each point) per sample. A file that is not a
version-1 cache of exactly that many samples raises pc2.Pc2Error, whose message names the file
and what is wrong.
"""
import os
import struct
import sys
from array import array

HEADER = struct.Struct("<12siiffi")
MAGIC = b"POINTCACHE2\0"


class Pc2Error(ValueError):
    """The file is not a whole PC2 cache."""


def read(path):
    with open(path, "rb") as f:
        data = f.read()
    name = os.path.basename(path)
    if len(data) < HEADER.size:
        raise Pc2Error(f"{name}: {len(data)} bytes, shorter than the {HEADER.size}-byte header")
    header = HEADER.unpack_from(data)
    magic, version, points, _, _, count = header
    if magic != MAGIC or version != 1:
        raise Pc2Error(f"{name}: header {magic!r} version {version}, not {MAGIC!r} version 1")
    if points < 0 or count < 0:
        raise Pc2Error(f"{name}: {points} points and {count} samples in the header")
    expected = HEADER.size + count * points * 12
    if len(data) != expected:
        raise Pc2Error(f"{name}: {len(data)} bytes, expected {expected} for {count} samples of "
                       f"{points} points")
    values = array("f")
    values.frombytes(data[HEADER.size:])
    if sys.byteorder != "little":
        values.byteswap()
    n = 3 * points
    return header, [values[i * n:(i + 1) * n] for i in range(count)]
