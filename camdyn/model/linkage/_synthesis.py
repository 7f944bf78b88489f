"""Path-generation synthesis: the cam of a cam-linkage whose tracing point must follow a closed path exactly."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import equinox as eqx
import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import NumericalError
from ..._core.jit import device_array, stored
from ..._core.units import TWO_PI
from ...schema import FollowerSpec, MechanismSpec, PathSpec, parse
from ..motion import HermiteMotion
from ..paths import Path, build_path, parse_path
from ._batch import N_GRID, padded, vmap_scalar, where_point
from ._chains import CCMChain, check_ccm_slider, check_follower_side, make_chain
from ._crank import CrankDyad, build_crank
from ._extremes import Extremes, find_extremes
from ._forward import ccm_forward, oscillating_forward, pitch_contour
from ._motion import CamLinkMotion, joint_points, sample, tabulate, with_breaks


def parse_mechanism(mech: dict | MechanismSpec) -> MechanismSpec:
    """A validated ``[mechanism]`` table (a :class:`camdyn.schema.MechanismSpec`); errors name ``mechanism.<key>``."""
    return mech if isinstance(mech, MechanismSpec) else parse(MechanismSpec, mech, "mechanism")


@dataclass(frozen=True)
class Synthesis:
    """Result of :func:`synthesize_motion`.

    ``motion``: the follower motion (:class:`CamLinkMotion`); ``tabulated``: its quintic Hermite table, which
    the case hands to the dynamics (exact at the knots, error in ``summary["motion_table_error"]``); ``follower``:
    the cam-follower geometry in the shared conventions of :mod:`camdyn.model.geometry` (cam centre at the
    origin). ``json()`` gives the summary for ``check --json``; :meth:`linkage_at` the joint positions for
    drawings.
    """

    motion: CamLinkMotion
    tabulated: HermiteMotion
    follower: FollowerSpec
    path_spec: PathSpec
    mechanism: MechanismSpec
    summary: dict
    theta_deg: np.ndarray  # cam angles of the arrays below
    pitch: np.ndarray  # (n, 2) roller centre in the cam frame, mm (Ye & Smith eq. 6)
    contour: np.ndarray  # (n, 2) cam contour in the cam frame, mm (eqs. 7-8)
    path_xy: np.ndarray  # (n, 2) target points at the same cam angles, case frame
    traced_xy: np.ndarray  # (n, 2) forward check: points traced by the linkage driven by the cam
    sharp_corners: bool = False
    warnings: list[str] = field(default_factory=list)

    @property
    def path_error_mm(self) -> float:
        """How far (mm) the linkage driven by the cam misses the path at worst: the forward check."""
        return float(self.summary["max_path_error_mm"])

    @property
    def least_transmission_deg(self) -> float:
        """The least transmission angle (deg) of the driven dyads over the path (a CCM's coupler-link and
        link-slider, an oscillating mechanism's coupler-follower)."""
        return min(
            float(self.summary[k]) for k in ("min_transmission_angle_deg", "min_slider_angle_deg") if k in self.summary
        )

    def json(self) -> dict:
        out = dict(self.summary)
        out.update(
            sharp_corners=self.sharp_corners,
            warnings=list(self.warnings),
            theta_deg=self.theta_deg.tolist(),
            pitch=self.pitch.tolist(),
            contour=self.contour.tolist(),
            path_xy=self.path_xy.tolist(),
            traced_xy=self.traced_xy.tolist(),
        )
        return out

    def linkage_at(self, theta_deg: ArrayLike) -> dict[str, np.ndarray]:
        """Joint positions (case frame, mm) at cam angles ``theta_deg``: name -> (n, 2).

        CCM: A (cam centre), B (crank pin), T (tracing point), C (coupler joint), E (slider pin).
        Oscillating: O (cam centre), A (crank pin), B, F (tracing point), C, D (pivot), E (roller centre).
        """
        m = with_breaks(self.motion, ())
        th = np.deg2rad(np.atleast_1d(np.asarray(theta_deg, dtype=float)))
        u = padded(sample, m, np.asarray(th))[0]
        crank = np.asarray(m.theta0) + float(m.sense) * np.asarray(th)
        pts = {k: v for k, v in padded(joint_points, m.chain, u, crank).items() if np.ndim(v) == 2}
        c0 = np.asarray(m.chain.center)
        out = {k: v + c0 for k, v in pts.items()}
        r = float(m.crank_dyad.r)
        pin = r * np.column_stack([np.cos(crank), np.sin(crank)]) + c0
        centre = np.broadcast_to(c0, pin.shape).copy()
        if isinstance(m.chain, CCMChain):
            out.update(A=centre, B=pin)
        else:
            out.update(O=centre, A=pin, D=np.broadcast_to(np.asarray(m.chain.pivot) + c0, pin.shape).copy())
        return out


def _crank_lengths(ext: Extremes, ms: MechanismSpec) -> tuple[float, float]:
    """Crank and coupler (mm): Ye & Smith eq. 5 from the extremes of |OP|, or the table's, which must close."""
    if ms.crank is None:  # Ye & Smith eq. 5
        r, coupler = (ext.d_max - ext.d_min) / 2.0, (ext.d_max + ext.d_min) / 2.0
        if r <= 0.0:
            raise NumericalError(
                "mechanism.crank",
                "the path-side point keeps a constant distance from the cam centre: eq. 5 gives no crank",
            )
        return r, coupler
    r, coupler = ms.crank, ms.coupler
    assert coupler is not None  # the schema: crank and coupler come together
    if ext.d_max > r + coupler + 1e-6:
        raise NumericalError(
            where_point(ext.i_max),
            f"crank dyad cannot close: reach missed by {ext.d_max - r - coupler:.4g} mm (|cam centre to path-side "
            f"point| = {ext.d_max:.6g} mm > crank + coupler = {r + coupler:g} mm)",
        )
    if ext.d_min < abs(r - coupler) - 1e-6:
        raise NumericalError(
            where_point(ext.i_min),
            f"crank dyad cannot close: reach missed by {abs(r - coupler) - ext.d_min:.4g} mm (|cam centre to "
            f"path-side point| = {ext.d_min:.6g} mm < |crank - coupler| = {abs(r - coupler):g} mm)",
        )
    return r, coupler


def _cam_angle_table(tab: np.ndarray, u_grid: np.ndarray, ms: MechanismSpec, dyad: CrankDyad):
    """The crank's sense and the unwrapped cam-angle table over the path grid from ``tab``, the motion's
    :func:`tabulate` there: (tab_u, tab_theta, sense, follower coordinate at each u). Refuses a linkage that
    cannot be assembled, a crank that reverses, and one that does not turn exactly once per loop."""
    if not np.all(np.isfinite(tab[:, :2])):
        i = int(np.argmax(~np.isfinite(tab[:, :2]).all(axis=1)))
        raise NumericalError(where_point(i), "the linkage cannot be assembled here (NaN position)")
    raw = np.unwrap(np.append(tab[:, 0], tab[0, 0]))
    turn = raw[-1] - raw[0]
    slope = tab[:, 2]
    sense = 1.0 if turn > 0 else -1.0
    bad = np.flatnonzero(sense * slope <= 0.0)
    if bad.size:
        i = int(bad[0])
        hint = (
            f"; try crank_mode = {-ms.crank_mode}"
            if dyad.n_switch
            else "; with crank and coupler from eq. 5 it passes its collinear positions instead"
        )
        raise NumericalError(
            where_point(i),
            f"the crank would reverse here (dtheta/du changes sign: {math.degrees(slope[i]):.4g} deg per unit u "
            f"against a net turn of {math.degrees(turn):.1f} deg){hint}",
        )
    if abs(abs(turn) - TWO_PI) > 1e-6:
        raise NumericalError(
            "mechanism.cam_center",
            f"the crank turns {math.degrees(turn):.1f} deg while the point runs once round the path; it must turn "
            "exactly once (360 deg)",
        )
    tab_theta = np.append(sense * (raw[:-1] - raw[0]), TWO_PI)
    return np.append(u_grid, 1.0), tab_theta, sense, tab[:, 1]


def _break_angles(core: CamLinkMotion, pth: Path) -> tuple[float, ...]:
    """Cam angles (deg) of the path's curvature and tangent breaks, exact: the table's linear interpolation would
    miss them by up to ~1e-5 rad, enough to put a jump of s'' inside an interval of the dynamics' step
    controller or the Hermite table."""
    brk_u = sorted(set(pth.breaks_u) | set(pth.sharp_u))
    brk_theta = vmap_scalar(core.cam_angle, np.asarray(brk_u, dtype=float)) if brk_u else np.zeros(0)
    return tuple(sorted({round(float(b) % TWO_PI * 180 / math.pi, 9) % 360.0 for b in brk_theta}))


def _build_motion(pth: Path, ms: MechanismSpec, u_grid: np.ndarray, warnings: list[str]):
    """The chain, the crank dyad and the follower motion of the mechanism: (motion, crank, coupler, extremes)."""
    chain = make_chain(pth, ms, 1.0, 1.0)
    check_follower_side(chain, ms, u_grid)
    ext = find_extremes(chain, u_grid)
    r, coupler = _crank_lengths(ext, ms)
    chain = make_chain(pth, ms, r, coupler)
    dyad, notes = build_crank(chain, r, coupler, ext, ms.crank_mode, pth)
    warnings += notes
    unit = ms.kind.motion_unit
    a = device_array
    proto = CamLinkMotion(
        chain=chain,
        crank_dyad=dyad,
        theta0=a(0.0),
        out0=a(0.0),
        tab_u=a(np.zeros(N_GRID + 1)),
        tab_theta=a(np.zeros(N_GRID + 1)),
        sense=a(1.0),
        unit=unit,
        breaks_deg=(),
    )
    th0 = float(padded(tabulate, proto, [0.0])[0, 0])
    proto = eqx.tree_at(lambda m: m.theta0, proto, a(th0))
    tab = padded(tabulate, proto, u_grid)
    if isinstance(chain, CCMChain):
        pts0 = padded(joint_points, chain, u_grid, tab[:, 0] + th0)
        check_ccm_slider(chain, pts0, ms)
    tab_u, tab_theta, sense, out = _cam_angle_table(tab, u_grid, ms, dyad)
    core = CamLinkMotion(
        chain=chain,
        crank_dyad=dyad,
        theta0=a(th0),
        out0=a(float(out.min())),
        tab_u=a(tab_u),
        tab_theta=a(tab_theta),
        sense=a(sense),
        unit=unit,
        breaks_deg=(),
    )
    return core, r, coupler, ext


def _table_error(
    tabulated: HermiteMotion, motion: CamLinkMotion, s2_range: float, summary: dict, warnings: list[str]
) -> None:
    """How far the quintic Hermite table the dynamics read is from the exact motion, in ``summary``; warns if it
    misses the exact s'' by more than 1e-4 of its range."""
    tab_err = tabulated.max_error(motion)
    summary["motion_table_error"] = dict(zip(("s", "s1", "s2", "s3"), map(float, tab_err), strict=True))
    if tab_err[2] > 1e-4 * max(s2_range, 1e-12):
        warnings.append(
            f"the tabulated follower motion misses the exact s'' by up to {tab_err[2]:.3g} per rad^2; the dynamics "
            "use the table"
        )


def synthesize_motion(path: dict | PathSpec, mechanism: dict | MechanismSpec, reuse: bool = False) -> Synthesis:
    """Synthesize the cam of a combined cam-linkage so that the tracing point follows ``path`` exactly.

    ``path``, ``mechanism``: the ``[path]`` and ``[mechanism]`` tables (see :class:`PathSpec`,
    :class:`MechanismSpec`). Raises :class:`InputError` for invalid tables and :class:`NumericalError` for a
    dyad that cannot close or a crank that would reverse (naming the path point). ``reuse``: read the synthesis
    an earlier process stored for the same tables (:func:`camdyn._core.jit.stored`; a case's, checked again and
    again), else compute and store it; ``synthesis_time_s`` is the time taken here either way.
    """
    t_start = time.perf_counter()
    ps, ms = parse_path(path), parse_mechanism(mechanism)
    if not reuse:
        return _synthesize(ps, ms, t_start)
    syn = stored("synthesis", ps.model_dump_json() + ms.model_dump_json(), lambda: _synthesize(ps, ms, t_start))
    return replace(syn, summary=dict(syn.summary, synthesis_time_s=time.perf_counter() - t_start))


def _synthesize(ps: PathSpec, ms: MechanismSpec, t_start: float) -> Synthesis:
    """:func:`synthesize_motion` of validated tables; ``t_start``: its start (``time.perf_counter``)."""
    pth = build_path(ps)
    warnings: list[str] = []
    sharp = bool(pth.sharp_u)
    core, r, coupler, ext = _build_motion(pth, ms, np.arange(N_GRID) / N_GRID, warnings)
    motion = with_breaks(core, _break_angles(core, pth))
    # the consumers that evaluate the motion millions of times (ODE right-hand side, sweeps) read a table
    tabulated = HermiteMotion.from_motion(motion)
    # samples at 1-degree steps: motion, forward check, pitch and contour
    theta = np.deg2rad(np.arange(360.0))
    u_s, sv = padded(sample, core, theta)
    step = theta[1] - theta[0]
    s2 = (np.roll(sv[:, 1], -1) - np.roll(sv[:, 1], 1)) / (
        2 * step
    )  # a scale for the table's error; exact: motion(theta)[2]
    vals = np.vstack([sv.T, s2])
    th0, sense = float(core.theta0), float(core.sense)
    crank_s = th0 + sense * theta
    target = vmap_scalar(pth.point, u_s)
    pts = padded(joint_points, core.chain, u_s, crank_s)
    a_pin = r * np.column_stack([np.cos(crank_s), np.sin(crank_s)])
    forward = ccm_forward if ms.type == "ccm" else oscillating_forward
    follower, traced, pos, vel, extra = forward(motion, tabulated, ms, vals, pts, a_pin, coupler, sense, warnings)
    err = float(np.max(np.linalg.norm(traced - target, axis=1)))
    rr = ms.roller_radius
    pitch, contour, _ = pitch_contour(pos, vel, theta, sense, rr)
    if sharp:
        warnings.append(
            "the path has sharp corners (corner_radius = 0): the follower velocity jumps there, so its acceleration "
            "is unbounded; give the corners a radius"
        )
    summary = {
        "mechanism": ms.type,
        "crank_mm": r,
        "coupler_mm": coupler,
        "start_angle_deg": (math.degrees(th0) + 180.0) % 360.0 - 180.0,
        "rotation": "ccw" if sense > 0 else "cw",
        "lob_min_mm": ext.d_min,
        "lob_max_mm": ext.d_max,
        "u_lob_min": ext.u_min[0],
        "u_lob_max": ext.u_max[0],
        "switches": [
            {
                "u": float(us),
                "cam_angle_deg": float(np.interp(us, np.asarray(core.tab_u), np.asarray(core.tab_theta)))
                * 180
                / math.pi,
            }
            for us in np.asarray(core.crank_dyad.u_sw)[: core.crank_dyad.n_switch]
        ],
        "max_path_error_mm": err,
        "base_radius_mm": follower.base_radius,
        "roller_radius_mm": rr,
        "synthesis_time_s": time.perf_counter() - t_start,
        **extra,
    }
    _table_error(tabulated, motion, float(np.ptp(vals[2])), summary, warnings)
    stroke = float(motion.kind.motion_to_lift(vals[0].max() - vals[0].min()))  # mm, or deg of swing
    summary["swing_deg" if motion.kind.rotary else "stroke_mm"] = stroke
    return Synthesis(
        motion=motion,
        tabulated=tabulated,
        follower=follower,
        path_spec=ps,
        mechanism=ms,
        summary=summary,
        theta_deg=np.arange(360.0),
        pitch=pitch,
        contour=contour,
        path_xy=target,
        traced_xy=traced,
        sharp_corners=sharp,
        warnings=warnings,
    )
