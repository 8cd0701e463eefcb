#!/usr/bin/env python3
"""Writes the crafted mesh pyramids of tests/fuzz/regressions/pyramid/ from the seed
tests/fuzz/corpus/pyramid/msh_200m.tpyr (a version-3 pyramid: docs/formats.md). Each is
a case a reader once let through or should refuse; the regression test fixes their
checksums first (pyramid_fix_checksums), so each reaches the check it is about.
  tests/fuzz/make_pyramid_regressions.py   # rewrites the folder's crafted_*.tpyr
"""
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))
seed = open(os.path.join(here, "corpus/pyramid/msh_200m.tpyr"), "rb").read()
out = os.path.join(here, "regressions/pyramid")

wkt = struct.unpack_from("<I", seed, 84)[0]
levels_at = 88 + wkt + 8          # after the CRS and the digest
block_at = levels_at + 4          # the one block: box (24 bytes), level count, errors, slopes


def patched(at, fmt, value, data=seed):
    b = bytearray(data)
    struct.pack_into(fmt, b, at, value)
    return bytes(b)


cases = {
    # A block's level count 0xFFFFFFFF (int(nl) was -1: 16 GiB reserved, killed).
    "block_levels_max": patched(block_at + 24, "<I", 0xFFFFFFFF),
    # The level count of the whole file past what its blocks have.
    "levels_max": patched(levels_at, "<I", 0xFFFFFFFF),
    # Blocks of 2 cells on a 46341 x 46341 grid: 5.4e8 blocks the header cannot hold.
    "tiny_blocks_big_grid": patched(32, "<Q", 46341, patched(24, "<Q", 46341, patched(20, "<I", 2))),
    # origin_x = inf (it passed the grid comparison).
    "origin_inf": patched(40, "<d", float("inf")),
    # Every box at height 0: the tiles' vertices are not in their blocks' boxes.
    "box_zero": patched(block_at + 8, "<f", 0.0, patched(block_at + 20, "<f", 0.0)),
    # A block's error NaN.
    "error_nan": patched(block_at + 32, "<f", float("nan")),
    # The CRS's length past the header.
    "wkt_huge": patched(84, "<I", 0x7FFFFFFF),
    # Version 0, and a version from the future.
    "version_0": patched(8, "<I", 0),
    "version_99": patched(8, "<I", 99),
    # The header's size past the file.
    "header_past_end": patched(12, "<Q", len(seed) + 1),
    # Cut in its tiles.
    "truncated": seed[: len(seed) - 100],
}
for name, data in cases.items():
    open(os.path.join(out, "crafted_" + name + ".tpyr"), "wb").write(data)
print(f"{len(cases)} cases in {out}")
