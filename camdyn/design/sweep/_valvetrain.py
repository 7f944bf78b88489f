"""The jump map of a valvetrain: the two-mass model at every (speed, valve spring rate) point, one point at a time
(:class:`camdyn.model.dynamics.ValvePoint`: the exact linear solution where every contact stays closed, else
:func:`camdyn.model.dynamics.valvetrain_response`, event driven on diffrax); a modest grid, honest where the
batched single-follower map would not be (it knows no lash, seat or float).

At each point: the least cam-contact force over the valve event (0 where the cam contact opens while the valve is
off its seat: float), whether the valve floats and whether it bounces (leaves its seat after closing by more than
the seat's micro-bounce tolerance), its seating velocity and bounce height, and the largest gap at the valve: how
far the valve is above where the cam would hold it, ``x_v - max(r s - lash, 0)``, over the revolution. The seat
bounds it: the valve's lift is never below 0, so a valve that flies is caught by its seat, not by a profile that
lets it fall through. With a ``[spring]`` part the case's valve spring is held at every rate: its own mass on the
valve as ``check`` puts it (its lumped third, or its surge chain), and its coil bind, the other stop: a valve whose
flight would compress the spring to solid is stopped there (its gap counted to solid, and
``coil_bind_clearance_mm`` negative by the overshoot of the model, which does not carry the solid stop itself).
"""

from __future__ import annotations

import numpy as np

from ..._core.errors import InputError, NumericalError
from ..._core.progress import Progress, counter
from ..._core.units import RPM
from ...model import dynamics as dyn
from ...model.case import Case, with_valvetrain_keys
from ..parts import resolve_spring
from ..valvetrain import spring_notes
from ._grid import check_grid_size
from ._result import STATUS_OK, JumpMap, ValveMap, failed


def valvetrain_map(case: Case, speeds_rpm, spring_rates=None, *, progress: Progress | None = None) -> JumpMap:
    """The jump map of a ``[valvetrain]`` case over ``speeds_rpm`` x ``spring_rates`` (the valve spring's rate,
    N/mm at the valve; default the case's own), the preload kept the case's."""
    case = resolve_spring(case)  # [spring]: the valve spring's own mass on the valve and its coil bind, as check
    vt = case.valvetrain
    assert vt is not None and case.spec.dynamics.spring_rate is not None  # the caller's: a [valvetrain] case
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    own = float(case.spec.dynamics.spring_rate)
    rates = np.atleast_1d(np.asarray(spring_rates if spring_rates is not None else [own], dtype=float))
    check_grid_size(speeds.size, rates.size)
    values = np.concatenate([speeds, rates])
    if not (speeds.size and rates.size and np.all(values > 0) and np.all(np.isfinite(values))):
        raise InputError("sweep", "speeds and spring rates must be positive and finite")
    shape = (speeds.size, rates.size)
    least, gap, seat_v, bounce_h, clearance = (np.full(shape, np.nan) for _ in range(5))
    solid_mm = case.spring.travel_to_solid_mm if case.spring is not None else None
    floated, bounced = np.zeros(shape, bool), np.zeros(shape, bool)
    status = np.full(shape, STATUS_OK, dtype=object)
    tick = counter(progress, "two-mass valvetrain model (one point at a time)", speeds.size * rates.size)
    for j, rate in enumerate(rates):
        model = with_valvetrain_keys(case, dynamics={"spring_rate": float(rate)}).valvetrain
        assert model is not None  # with_valvetrain_keys rebuilds it
        for i, rpm in enumerate(speeds):
            try:
                point = dyn.ValvePoint(case.motion, model, float(rpm) * RPM)
                floated[i, j], bounced[i, j] = point.floated, point.bounced
                least[i, j] = point.least_event_force
                gap[i, j] = point.max_gap_mm(np.inf if solid_mm is None else solid_mm)
                if solid_mm is not None:
                    clearance[i, j] = solid_mm - point.max_valve_lift_mm
                seat_v[i, j], bounce_h[i, j] = point.seating_velocity, point.bounce_height_mm
            except NumericalError as err:
                status[i, j] = failed(str(err))
            except Exception as err:  # noqa: BLE001  (a bug at one point: flagged in its row, the map goes on)
                status[i, j] = failed(f"internal error in the two-mass model: {type(err).__name__}: {err}")
            tick(1)
    bad = status != STATUS_OK
    notes = list(spring_notes(case, "at every rate"))
    if solid_mm is not None and np.any(clearance < 0.0):
        notes.append(
            f"coil bind: the valve's flight reaches its spring's solid height at {int(np.sum(clearance < 0.0))} "
            "point(s) (coil_bind_clearance_mm negative; the gap is counted to solid)"
        )
    if bad.any():
        notes.append(f"{int(bad.sum())} grid point(s) failed (status column, their numbers NaN)")
    return JumpMap(
        case=case.name,
        model="valvetrain",
        kind=case.kind,
        speeds_rpm=speeds,
        spring_rates=rates,
        min_force=least,
        separated=floated,
        max_gap=gap,
        contact_force=np.where(floated, -1.0, least),  # the float boundary: 0 between floated and held points
        speed_rpm=float(case.speed_rpm),
        spring_rate=own,
        preload=float(case.spec.dynamics.preload or 0.0),
        notes=tuple(notes),
        status=status,
        valve=ValveMap(bounced, seat_v, bounce_h, None if solid_mm is None else clearance),
    )
