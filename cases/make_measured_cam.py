"""Regenerate cases/measured-cam.csv: a cam outline as a coordinate measuring machine would report it
(run: python cases/make_measured_cam.py).

The cam is an indexing cam designed with camdyn: dwell to 40 deg, a 30 mm modified-sine rise to 150 deg, dwell to
210 deg, a modified-sine return to 320 deg, dwell; translating roller follower (roller 15 mm, base radius 50 mm,
no offset), turning clockwise. Its exact contour is probed at 1500 points evenly spaced along the outline (about
0.26 mm apart), each displaced along the contour normal by Gaussian noise of 2 um standard deviation (seeded),
and written to 0.1 um. camdyn sees only the CSV.
"""

from pathlib import Path

import numpy as np

import camdyn

camdyn.enable_x64()
from camdyn.model.geometry import analyze  # noqa: E402  (after enable_x64: float64 before camdyn's JAX code loads)
from camdyn.model.motion import Program  # noqa: E402  (after enable_x64)
from camdyn.schema import FollowerSpec  # noqa: E402  (after enable_x64)

OUT = Path(__file__).with_name("measured-cam.csv")

SEGMENTS = [
    {"law": "dwell", "end": 40},
    {"law": "modified-sine", "end": 150, "lift": 30},
    {"law": "dwell", "end": 210},
    {"law": "modified-sine", "end": 320, "lift": -30},
    {"law": "dwell", "end": 360},
]
FOLLOWER = FollowerSpec(type="translating-roller", base_radius=50, roller_radius=15, rotation="cw")
POINTS, NOISE_MM, SEED = 1500, 0.002, 2024


def main(path: Path = OUT) -> None:
    geo = analyze(Program.from_segments(SEGMENTS), FOLLOWER)
    u = np.linspace(0.0, 1.0, 20001)
    xy = geo.contour_fn()(u)  # (2, m), closed: the last point is the first
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=1)))])
    at = np.interp(np.arange(POINTS) * arc[-1] / POINTS, arc, u)
    pts = geo.contour_fn()(at)
    eps = 1e-7
    tangent = geo.contour_fn()(at + eps) - geo.contour_fn()(at - eps)
    normal = np.stack([tangent[1], -tangent[0]]) / np.hypot(*tangent)
    normal *= np.sign(np.sum(normal * pts, axis=0))  # outward
    noisy = pts + normal * NOISE_MM * np.random.default_rng(SEED).standard_normal(POINTS)
    path.write_text("x_mm,y_mm\n" + "".join(f"{x:.4f},{y:.4f}\n" for x, y in noisy.T))
    print(f"wrote {path}: {POINTS} points, outline {arc[-1]:.1f} mm long")


if __name__ == "__main__":
    main()
