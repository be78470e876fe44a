#!/usr/bin/env python3
"""Makes ground_steel.x3p, the small measured-like map of the README's "Bring your own
surface" example: 256 x 256 points at 0.5 um spacing (128 um square), a self-affine
roughness (H = 0.8, rms 0.4 um) cut out of a larger periodic map so that it is NOT periodic,
a tilt of 2 mrad along x, and 37 missing points; stored as ISO 25178-72 x3p with 16-bit
integer heights (1 nm steps) and a valid-points mask, by the independent x3p writer of the
tests (tests/python/surface_writers.py).

    /usr/bin/python3 examples/surfaces/make_ground_steel.py
"""
import os
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "tests", "python"))
from surface_writers import write_x3p  # noqa: E402

rng = np.random.default_rng(20261125)
n_big, n, dx = 512, 256, 0.5e-6
qx = np.fft.fftfreq(n_big)[None, :]
qy = np.fft.fftfreq(n_big)[:, None]
q = np.hypot(qx, qy)
q_l, q_s = 1.0 / 128, 1.0 / 4  # wavelengths 128 and 4 points
amp = np.where((q >= q_l) & (q <= q_s), np.maximum(q, q_l) ** (-1.0 - 0.8), 0.0)
amp[0, 0] = 0.0
h = np.fft.ifft2(amp * np.exp(2j * np.pi * rng.random(amp.shape))).real[:n, :n]
h *= 0.4e-6 / h.std()
x = np.arange(n) * dx
h += 2e-3 * x[None, :]
missing = rng.choice(n * n, size=37, replace=False)
h.flat[missing] = np.nan
write_x3p(os.path.join(here, "ground_steel.x3p"), h - np.nanmean(h), n * dx, n * dx, ztype="I", zinc=1e-9)
print("wrote", os.path.join(here, "ground_steel.x3p"))
