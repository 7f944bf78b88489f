"""Many cams on one main shaft: every cam checked at the machine speed, the timing diagram, the summed shaft torque
and the flywheel, and the clearance between followers that share space.

A cam at ``phase`` (deg) turns with the main shaft: its cam angle is the machine angle less its phase. Its drive
torque is the one ``camdyn check`` computes at the machine speed (:func:`camdyn.design.parts.case_drive`), moved to
machine angles; the shaft carries the sum, and the sum's peak, RMS, mean, energy swing and flywheel come from
:class:`camdyn.model.drive.DriveTorque`, as a single cam's do.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._core.errors import CamdynError
from .._core.outputs import safe_stem
from .._core.progress import Progress, counter
from .._core.units import RPM, THETA_GRID
from ..model.case import build_case
from ..model.drive import DriveTorque
from ..schema.machine import ClearanceSpec, MachineFile, load_machine
from ._check import Check, CheckKind
from .checks import CheckReport, run_check
from .table import csv_text

DWELL_TOLERANCE = 1e-6  # of the largest |ds/dtheta|: a follower slower than this stands still
MIN_DWELL_DEG = 1.0  # a shorter stand-still is a turning point, not a dwell


def machine_angles() -> np.ndarray:
    """The machine angles of every result, deg: THETA_GRID equal steps of [0, 360) (0.1 deg)."""
    return np.arange(THETA_GRID) * (360.0 / THETA_GRID)


def at_machine_angles(theta_deg, values, phase_deg: float) -> np.ndarray:
    """``values`` given at cam angles ``theta_deg`` (one revolution), at the machine angles: the cam angle is the
    machine angle less the phase (periodic linear interpolation; exact where the phase is a multiple of the step)."""
    cam_deg = np.round((machine_angles() - phase_deg) % 360.0, 9)
    return np.interp(cam_deg, np.asarray(theta_deg, dtype=float), np.asarray(values, dtype=float), period=360.0)


def dwell_spans(theta_deg: np.ndarray, velocity: np.ndarray) -> tuple[tuple[float, float], ...]:
    """The dwells (start, end) in deg of a motion sampled on equal steps of one revolution: runs of at least
    :data:`MIN_DWELL_DEG` where |ds/dtheta| stays under :data:`DWELL_TOLERANCE` of its largest. A dwell through
    0 deg is one span with end < start."""
    v = np.abs(np.asarray(velocity, dtype=float))
    still = v <= DWELL_TOLERANCE * max(float(v.max()), 1e-300)
    if still.all():
        return ((0.0, 360.0),)
    step = 360.0 / still.size
    start = int(np.argmin(still))  # a moving sample: walk the revolution from it, so no run is cut at 0 deg
    spans, run = [], None
    for k in range(start, start + still.size + 1):
        if still[k % still.size]:
            run = k if run is None else run
        elif run is not None:
            if (k - 1 - run) * step >= MIN_DWELL_DEG:  # from the first still sample to the last
                spans.append((float(theta_deg[run % still.size]), float(theta_deg[(k - 1) % still.size])))
            run = None
    return tuple(sorted(spans))


@dataclass(frozen=True)
class MachineCam:
    """One cam of the machine, checked at the machine speed, with its lift and torque at the machine angles."""

    name: str
    case_file: str  # as the machine file names it
    phase_deg: float
    check: CheckReport
    lift: np.ndarray  # the follower's lift at the machine angles: mm, or deg of an arm's swing
    torque: np.ndarray  # its shaft torque at the machine angles, N*m
    dwells_deg: tuple[tuple[float, float], ...]  # machine angles; end < start where a dwell runs through 0

    @property
    def verdict(self) -> str:
        return self.check.verdict

    @property
    def lift_unit(self) -> str:
        return self.check.case.kind.lift_unit

    @property
    def normalized_lift(self) -> np.ndarray:
        """The lift over its stroke: 0 at its least, 1 at its largest (0 throughout for a cam that does not move)."""
        stroke = float(np.ptp(self.lift))
        return (self.lift - self.lift.min()) / stroke if stroke > 0.0 else np.zeros_like(self.lift)

    @property
    def speed_margin(self) -> float | None:
        """Its dynamic jump speed over the machine speed (x); None: no jump at any speed."""
        margin = self.check.find(CheckKind.SPEED_MARGIN)
        return None if margin is None else margin.value

    @property
    def failed(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.check.checks if not c.ok)

    @property
    def peak_torque(self) -> float:
        """Largest |torque| of this cam, N*m."""
        return float(np.max(np.abs(self.torque)))

    @property
    def peak_torque_at_deg(self) -> float:
        """The machine angle of :attr:`peak_torque`, deg (its ``check``'s drive peak plus the phase)."""
        return float(machine_angles()[int(np.argmax(np.abs(self.torque)))])

    def json(self) -> dict:
        return {
            "name": self.name,
            "case": self.case_file,
            "phase_deg": self.phase_deg,
            "verdict": self.verdict,
            "failed_checks": list(self.failed),
            "stroke": float(np.ptp(self.lift)),
            "stroke_unit": self.lift_unit,
            "peak_torque_N_m": self.peak_torque,
            "peak_torque_at_deg": self.peak_torque_at_deg,
        }


@dataclass(frozen=True)
class Clearance:
    """The gap between two followers over a revolution (see :class:`camdyn.schema.machine.ClearanceSpec`)."""

    between: tuple[str, str]
    min_gap_mm: float
    gap_mm: np.ndarray  # at the machine angles

    @property
    def least_gap_mm(self) -> float:
        return float(self.gap_mm.min())

    @property
    def least_gap_at_deg(self) -> float:
        return float(machine_angles()[int(np.argmin(self.gap_mm))])

    @property
    def check(self) -> Check:
        return CheckKind.CLEARANCE.check(self.least_gap_mm, self.min_gap_mm)

    def json(self) -> dict:
        return {
            "between": list(self.between),
            "min_gap_mm": self.min_gap_mm,
            "least_gap_mm": self.least_gap_mm,
            "least_gap_at_deg": self.least_gap_at_deg,
            "ok": self.check.ok,
        }


def clearance(spec: ClearanceSpec, cams: dict[str, MachineCam]) -> Clearance:
    """``gap - closes[0] * s_a - closes[1] * s_b`` at every machine angle."""
    (a, b), (ka, kb) = spec.between, spec.closes
    return Clearance((a, b), float(spec.min_gap), spec.gap - ka * cams[a].lift - kb * cams[b].lift)


@dataclass(frozen=True)
class MachineResult:
    """``camdyn machine``: every cam's check at the machine speed, the shaft's drive, the clearances."""

    name: str
    source: Path | None
    description: str
    speed_rpm: float
    cams: tuple[MachineCam, ...]
    drive: DriveTorque  # the sum of the cams' torques, at the machine angles
    clearances: tuple[Clearance, ...] = ()

    @property
    def theta_deg(self) -> np.ndarray:
        return self.drive.theta_deg

    @property
    def verdict(self) -> str:
        ok = all(c.verdict == "pass" for c in self.cams) and all(g.check.ok for g in self.clearances)
        return "pass" if ok else "fail"

    def json(self) -> dict:
        """The ``machine --json`` document."""
        return {
            "machine": self.name,
            "verdict": self.verdict,
            "speed_rpm": self.speed_rpm,
            "cams": [c.json() for c in self.cams],
            "drive": self.drive.json(),
            "clearances": [g.json() for g in self.clearances],
        }

    def columns(self) -> dict[str, np.ndarray]:
        """The CSV's columns: ``theta_deg``, ``torque_<cam>_N_m`` per cam, ``torque_total_N_m``."""
        cols = {"theta_deg": self.theta_deg}
        cols |= {f"torque_{safe_stem(c.name)}_N_m": c.torque for c in self.cams}
        return cols | {"torque_total_N_m": self.drive.torque}

    @property
    def csv(self) -> str:
        return csv_text(self.columns())


def _shifted(span: tuple[float, float], phase_deg: float) -> tuple[float, float]:
    """A span of cam angles (deg) as machine angles; the whole revolution stays whole."""
    if span == (0.0, 360.0):
        return span
    a, b = (float(x) for x in np.round((np.asarray(span) + phase_deg) % 360.0, 9))
    return a, b


def _named(cam, i: int, err: CamdynError) -> CamdynError:
    where = f"cam[{i}].case {cam.path.name}" + (f": {err.where}" if err.where else "")
    return type(err)(where, err.message)


def run_machine(machine: MachineFile, *, progress: Progress | None = None) -> MachineResult:
    """Check every cam of ``machine`` at its speed, sum the shaft torque and judge the clearances."""
    spec = machine.spec
    rpm = float(spec.speed)
    tick = counter(progress, f"{machine.name}: cams checked at {rpm:g} rpm", len(machine.cams))
    cams = []
    for i, (cam, cam_spec) in enumerate(zip(machine.cams, spec.cam, strict=True)):
        try:
            case = build_case(cam.spec, source=cam.path)
            report = run_check(case, rpm)
        except CamdynError as err:
            raise _named(cam, i, err) from None
        theta_deg, values = case.motion.sample(THETA_GRID)
        to_file_unit = np.rad2deg(1.0) if case.oscillating else 1.0  # an arm's swing in deg, as the case file has it
        lift = at_machine_angles(theta_deg, values[0] * to_file_unit, cam.phase_deg)
        dwells = tuple(_shifted(span, cam.phase_deg) for span in dwell_spans(theta_deg, values[1]))
        assert report.drive is not None  # check computes the camshaft drive of every case
        torque = at_machine_angles(report.drive.theta_deg, report.drive.torque, cam.phase_deg)
        cams.append(MachineCam(cam.name, cam_spec.case, cam.phase_deg, report, lift, torque, dwells))
        tick()
    total = np.sum([c.torque for c in cams], axis=0)
    drive = DriveTorque(rpm * RPM, machine_angles(), total, float(spec.drive.speed_fluctuation))
    by_name = {c.name: c for c in cams}
    gaps = tuple(clearance(g, by_name) for g in spec.clearance)
    return MachineResult(machine.name, machine.source, spec.description, rpm, tuple(cams), drive, gaps)


def check_machine(path: str | Path, *, progress: Progress | None = None) -> MachineResult:
    """Read, validate and check a machine file (see :func:`run_machine`)."""
    return run_machine(load_machine(path), progress=progress)
