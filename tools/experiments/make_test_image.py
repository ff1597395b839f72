"""Writes the image target used by the experiments: a 128x128 greyscale PFM
with a smooth gradient, a bright disc, an empty ring and an empty bar, so it
has smooth parts, jumps and zero-density regions. Usage: make_test_image.py OUT.pfm"""
import math
import os
import struct
import sys

W = H = 128
rows = []
for j in range(H):  # PFM rows run bottom to top
    y = (j + 0.5) / H
    row = []
    for i in range(W):
        x = (i + 0.5) / W
        v = 0.2 + 0.8 * x * y                             # smooth gradient
        r = math.hypot(x - 0.62, y - 0.6)
        if r < 0.18:
            v = 3.0                                        # bright disc
        elif r < 0.24:
            v = 0.0                                        # empty ring
        if 0.15 < x < 0.25 and y < 0.7:
            v = 0.0                                        # empty bar
        row.append(v)
    rows.append(row)
out = sys.argv[1]
with open(out + ".tmp", "wb") as f:
    f.write(b"Pf\n%d %d\n-1.0\n" % (W, H))
    for row in rows:
        f.write(struct.pack("<%df" % W, *row))
os.replace(out + ".tmp", out)
