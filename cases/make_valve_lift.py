"""Regenerate cases/valve-lift.csv: a made-up but realistic valve-lift table (run: python cases/make_valve_lift.py).

The lift is designed the way a valvetrain engineer lays out an event, with camdyn's own polynomial segments from
boundary conditions (Norton's method), every junction matched in velocity and acceleration (C2):

* base circle to 50 deg;
* opening ramp, 50 -> 75 deg: 0.25 mm, leaving at 0.55 mm/rad (0.0096 mm/deg): the clearance take-up;
* opening flank, 75 -> 165 deg: up to 10 mm, arriving at the nose with zero velocity and -14 mm/rad^2;
* closing flank, 165 -> 275 deg: back to 0.25 mm, longer and gentler than the opening (an asymmetric event);
* closing ramp, 275 -> 300 deg: 0.25 mm from 0.55 mm/rad, seating the valve softly; base circle to 360 deg.

The event lasts 250 deg of cam angle with a 10 mm peak. The table samples it every 1 deg and rounds the lift to
0.001 mm, as a supplier's table would give it; camdyn only ever sees the CSV.
"""

from pathlib import Path

import numpy as np

import camdyn

camdyn.enable_x64()
from camdyn.model.motion import Program  # noqa: E402  (after enable_x64: float64 before camdyn's JAX code loads)

OUT = Path(__file__).with_name("valve-lift.csv")

RAMP, V_OPEN, V_CLOSE, NOSE_ACC = 0.25, 0.55, 0.55, -14.0
SEGMENTS = [
    {"law": "dwell", "end": 50},
    {"law": "polynomial", "end": 75, "lift": RAMP, "end_velocity": V_OPEN},
    {"law": "polynomial", "end": 165, "lift": 10.0 - RAMP, "start_velocity": V_OPEN, "end_acceleration": NOSE_ACC},
    {"law": "polynomial", "end": 275, "lift": RAMP - 10.0, "start_acceleration": NOSE_ACC, "end_velocity": -V_CLOSE},
    {"law": "polynomial", "end": 300, "lift": -RAMP, "start_velocity": -V_CLOSE},
    {"law": "dwell", "end": 360},
]


def main(path: Path = OUT) -> None:
    program = Program.from_segments(SEGMENTS)
    problems = program.continuity_warnings() + program.polynomial_warnings()
    if problems:
        raise SystemExit("; ".join(problems))
    theta = np.arange(360.0)
    lift = np.asarray(program._eval(np, np.deg2rad(theta)))[0]
    rows = "".join(f"{t:g},{s:.3f}\n" for t, s in zip(theta, np.round(lift, 3) + 0.0, strict=True))
    path.write_text("theta_deg,lift_mm\n" + rows)
    print(f"wrote {path}: peak {lift.max():.3f} mm at {theta[lift.argmax()]:g} deg")


if __name__ == "__main__":
    main()
