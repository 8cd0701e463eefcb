#!/usr/bin/env python3
"""Line agreement of two frames of the same camera and layers (issue 52: a level-of-detail
frame against the full-detail frame). A line pixel is one whose colour is neither the mask's
white nor the background's (the colour of the top-left pixel), by more than `tol` in any
channel. Prints the share of A's line pixels within `radius` px of B's, and of B's within
`radius` px of A's, and the two counts.
Usage: line_agreement.py A.png B.png [radius=1] [tol=24]   (/usr/bin/python3: numpy, GDAL)"""
import sys

import numpy as np
from osgeo import gdal


def lines(path, tol):
    d = gdal.Open(path)
    a = np.stack([d.GetRasterBand(b + 1).ReadAsArray().astype(int) for b in range(3)], axis=-1)
    bg = a[0, 0]
    white = np.array([255, 255, 255])
    far_bg = np.abs(a - bg).max(axis=-1) > tol
    far_white = np.abs(a - white).max(axis=-1) > tol
    return far_bg & far_white


def dilate(m, r):
    out = m.copy()
    h, w = m.shape
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            src = m[max(0, -dy):h - max(0, dy), max(0, -dx):w - max(0, dx)]
            out[max(0, dy):h - max(0, -dy), max(0, dx):w - max(0, -dx)] |= src
    return out


def main():
    a_path, b_path = sys.argv[1], sys.argv[2]
    r = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    tol = int(sys.argv[4]) if len(sys.argv) > 4 else 24
    a, b = lines(a_path, tol), lines(b_path, tol)
    na, nb = int(a.sum()), int(b.sum())
    a_in_b = float((a & dilate(b, r)).sum()) / max(na, 1)
    b_in_a = float((b & dilate(a, r)).sum()) / max(nb, 1)
    print(f"{a_in_b:.4f} {b_in_a:.4f} {na} {nb}")


if __name__ == "__main__":
    main()
