"""Design-review reports: one A4 PDF per case and one PNG per page, made to be looked at.

``camdyn report CASE.toml ... -o DIR`` and ``camdyn check CASE.toml --report DIR`` write ``DIR/<case>.pdf`` and
``DIR/<case>-<n>-<page>.png``. The pages are the entries of :data:`PAGES`, in order; a page is a
:class:`Page` (file-name slug, title, a function drawing it on an A4 figure from a :class:`ReportData`, and
a predicate saying whether it applies to a case), so adding a page is adding one entry. Everything a page
shows comes from :class:`ReportData`: the check (:func:`camdyn.checks.run_check`, computed once) and
quantities derived from it on first use.

Files are written deterministically (no timestamps in the PDF; the same case gives the same bytes) and only
under names camdyn itself produces: a report overwrites ``<case>.pdf`` and ``<case>-<n>-<page>.png`` and removes
stale ``<case>-<n>-<page>.png`` pages from an earlier run, and touches nothing else.
"""

from __future__ import annotations

import math
import re
import textwrap
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Callable

import numpy as np

from .._core.errors import CamdynError, InputError
from .._core.outputs import output_dir, safe_stem
from .._core.progress import Progress, counter
from .._core.units import RPM

A4 = (8.27, 11.69)  # portrait, inches
DPI = 100  # PNG resolution: 827 x 1169 px per page

# One style for every figure: legible on A4 when printed or shown full screen.
STYLE = {
    "font.family": "DejaVu Sans",
    "font.size": 8.5,
    "axes.titlesize": 9.5,
    "axes.titleweight": "bold",
    "axes.titlelocation": "left",
    "axes.labelsize": 8.5,
    "axes.linewidth": 0.7,
    "axes.edgecolor": "#444444",
    "axes.grid": True,
    "grid.color": "#cccccc",
    "grid.linewidth": 0.5,
    "grid.alpha": 0.8,
    "xtick.labelsize": 7.5,
    "ytick.labelsize": 7.5,
    "xtick.major.width": 0.6,
    "ytick.major.width": 0.6,
    "legend.fontsize": 7.5,
    "legend.frameon": True,
    "legend.framealpha": 0.9,
    "legend.edgecolor": "#cccccc",
    "lines.linewidth": 1.2,
    "lines.solid_capstyle": "round",
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
    "path.simplify": True,
    "axes.formatter.use_mathtext": True,
    "axes.formatter.limits": (-4, 5),
    "svg.hashsalt": "camdyn",
}

# Colours with one meaning each, on every page.
C = {
    "kin": "#7f7f7f",  # kinematic (rigid follower, never leaves the cam)
    "dyn": "#1f5fa8",  # dynamic at the case speed
    "margin": "#e07b00",  # dynamic at speed_margin x speed
    "limit": "#c0392b",  # limits, failures, separations
    "ok": "#2e8540",
    "fail": "#c0392b",
    "break": "#999999",  # segment boundaries
    "cam": "#dfe4ea",
    "ink": "#222222",
    "grey": "#666666",
    "warn": "#a86800",
    "advice": "#1b6e75",
    "path": "#9ecae1",
    "traced": "#d62728",
    "constraint": "#b3b3b3",  # one cam angle's constraint on the spring
    "iso": "#7b4fa0",  # iso-lines of the peak spring force
}

_GRID = 3600  # angles per revolution of the dynamics (dynamics.response's default n)
_SPEEDS = 2000  # speeds of dynamics.dynamic_jump_speed's scan
_EPS_DEG = 1e-7  # one-sided limits at the motion's breaks
_MAP_SPEEDS, _MAP_RATES = 48, 24  # the spring-sizing page's jump map
_MAP_TOP = 0.25  # ... and the top of its axes (figure fraction)
_RIGHT = 0.87  # right edge of plot axes (room for the time-unit axes)
_LEFT = 0.11


def _deg_ticks(ax, every: float = 45.0) -> None:
    from matplotlib.ticker import MultipleLocator

    ax.set_xlim(0.0, 360.0)
    ax.xaxis.set_major_locator(MultipleLocator(every))


# ======================================================================================= data
@dataclass
class ReportData:
    """What the pages draw: the case, its check, and derived quantities (computed on first use)."""

    case: object  # case.Case
    check: object  # checks.CheckReport

    # ---------------------------------------------------------------- motion, in display units
    @property
    def oscillating(self) -> bool:
        return self.case.oscillating

    @property
    def omega(self) -> float:
        from .._core.units import RPM

        return self.check.speed_rpm * RPM

    @property
    def to_display(self) -> float:
        """Motion unit -> display unit: mm stays mm, an arm swing in rad is shown in degrees."""
        return 180.0 / math.pi if self.oscillating else 1.0

    @property
    def unit(self) -> str:
        return "deg" if self.oscillating else "mm"

    def _motion_values(self, theta_deg: np.ndarray) -> np.ndarray:
        """The motion (4, n) at any angles, in display units, evaluated on the 3600-point grid shape that the
        dynamics already compiled (a path motion compiles for seconds per new array shape)."""
        import jax.numpy as jnp

        from ..model.motion import evaluate

        n = _GRID
        flat = np.asarray(theta_deg, dtype=float).ravel()
        parts = []
        for i in range(0, flat.size, n):
            chunk = np.zeros(n)
            part = flat[i : i + n]
            chunk[: part.size] = part
            parts.append(np.asarray(evaluate(self.case.motion, jnp.deg2rad(jnp.asarray(chunk))))[:, : part.size])
        return np.concatenate(parts, axis=1) * self.to_display

    @cached_property
    def svaj(self) -> tuple[np.ndarray, np.ndarray]:
        """(theta_deg, values (4, n)) on a 0.25 deg grid plus both sides of every break, display units."""
        grid = np.linspace(0.0, 360.0, 1441)
        grid[-1] = 360.0 - _EPS_DEG
        b = np.asarray(self.case.motion.breaks_deg, dtype=float)
        th = np.unique(np.concatenate([grid, (b - _EPS_DEG) % 360.0, (b + _EPS_DEG) % 360.0]))
        return th, self._motion_values(th)

    @cached_property
    def jumps(self) -> list[tuple[float, int, float]]:
        """(angle deg, order 1 or 2, jump in display units) of the velocity and acceleration jumps at breaks."""
        b = np.asarray(self.case.motion.breaks_deg, dtype=float)
        th, vals = self.svaj
        out = []
        for deg in b:
            i, j = np.searchsorted(th, (deg - _EPS_DEG) % 360.0), np.searchsorted(th, (deg + _EPS_DEG) % 360.0)
            left, right = vals[:, i], vals[:, j]
            for order in (1, 2):
                jump = right[order] - left[order]
                if abs(jump) > 1e-6 * max(1.0, abs(left[order]), abs(right[order])):
                    out.append((float(deg), order, float(jump)))
        return out

    # ---------------------------------------------------------------------------- dynamics
    @cached_property
    def margin_rpm(self) -> float:
        return self.case.limits.speed_margin * self.check.speed_rpm

    @cached_property
    def margin_response(self):
        """The steady state at speed_margin x speed (forces in N), or the error message if it cannot be had."""
        from ..model import dynamics as dyn
        from ..design.checks import forces_in_newton

        try:
            resp = dyn.response(self.case.motion, self.case.model, self.margin_rpm * RPM)
            return forces_in_newton(self.case, resp)
        except CamdynError as err:
            return str(err)

    @cached_property
    def speed_sweep(self) -> dict:
        """Least interface force (N) against cam speed: kinematic (rigid) and, for a compliant train, the
        frequency-domain steady state (exact until the follower separates)."""
        import jax.numpy as jnp

        from ..model import dynamics as dyn
        from .._core.units import FFT_GRID, TWO_PI

        case, chk = self.case, self.check
        rpm = chk.speed_rpm
        top = 1.6 * max(self.margin_rpm, rpm)
        for j in (chk.dynamic["jump_speed_rpm"], chk.kinematic["jump_speed_rpm"]):
            if j is not None and j < 8.0 * rpm:
                top = max(top, 1.15 * j)
        speeds = np.linspace(top / _SPEEDS, top, _SPEEDS)  # the jump-speed scan's array shape: compiled already
        w = speeds * RPM
        # the kinematic force is a quadratic in the speed at every angle: three evaluations give it all
        # the very theta array (shape and JAX weak type) of dynamics.response, so its compiled force is reused
        theta = jnp.asarray(np.arange(_GRID) * (TWO_PI / _GRID)) if case.model.rigid else jnp.arange(_GRID) * (TWO_PI / _GRID)
        f = [np.asarray(dyn.kinematic_force_jit(case.motion, case.model, jnp.asarray(x, dtype=float), theta)) for x in (0.0, 1.0, -1.0)]
        a, b, c = 0.5 * (f[1] + f[2]) - f[0], 0.5 * (f[1] - f[2]), f[0]
        kin = w[:, None] ** 2 * a + w[:, None] * b + c
        if self.oscillating:
            kin = kin * self._newton_per_torque(np.asarray(theta))
        out = {"rpm": speeds, "kinematic": kin.min(axis=1), "linear": None}
        if not case.model.rigid:
            nf = FFT_GRID
            weight = None
            if self.oscillating:
                weight = jnp.asarray(self._newton_per_torque(np.arange(nf) * (TWO_PI / nf)))
            out["linear"] = np.asarray(dyn.linear_min_force(case.motion, case.model, jnp.asarray(w), nf, weight))
        return out

    # ----------------------------------------------------------------------------- springs
    @cached_property
    def sizing(self):
        """:func:`camdyn.sizing.size_spring` at the case's speed and speed_margin, or the reason it cannot apply."""
        from ..design.sizing import size_spring

        try:
            return size_spring(self.case)
        except CamdynError as err:
            return str(err)

    @cached_property
    def jump_map(self):
        """A small jump map at the case's preload over the sizing page's rates and the dynamics page's speeds
        (gaps not integrated: the map shows the least force and the jump boundary), or the error message."""
        from ..design.sweep import jump_map

        chk, sz = self.check, self.sizing
        rpm = chk.speed_rpm
        top = 1.6 * max(self.margin_rpm, rpm)
        for j in (chk.dynamic["jump_speed_rpm"], chk.kinematic["jump_speed_rpm"]):
            if j is not None:  # past the case's jump speeds, however fast: the map shows the jump boundary
                top = max(top, 1.15 * j)
        d = self.case.spec.dynamics
        k_cur = float(d.torsion_rate if self.oscillating else d.spring_rate)
        k_top = float(sz.region_rate[-1]) if not isinstance(sz, str) else 2.0 * k_cur
        speeds = np.linspace(top / _MAP_SPEEDS, top, _MAP_SPEEDS)
        rates = np.linspace(k_top / _MAP_RATES, k_top, _MAP_RATES)
        try:
            return jump_map(self.case, speeds, rates, gaps=False)
        except CamdynError as err:
            return str(err)

    def _newton_per_torque(self, theta_rad: np.ndarray) -> np.ndarray:
        from ..model.geometry import lever_arm_mm

        return 1000.0 / np.asarray(lever_arm_mm(self.case.motion, self.case.follower, theta_rad))


# ======================================================================================= pages
@dataclass(frozen=True)
class Page:
    """One report page: ``draw(fig, data)`` fills an A4 figure; ``applies(data)`` says whether the case has it."""

    slug: str  # file name part: <case>-<n>-<slug>.png
    title: str
    draw: Callable[[object, ReportData], None]
    applies: Callable[[ReportData], bool] = field(default=lambda data: True)


def _header(fig, data: ReportData, title: str, number: int, total: int) -> None:
    ver = _version()
    case = data.case
    fig.text(0.06, 0.975, case.name, size=15, weight="bold", va="top", color=C["ink"])
    fig.text(0.94, 0.973, f"{number}  {title}", size=12.5, ha="right", va="top", color=C["grey"])
    fig.add_artist(_hline(fig, 0.948))
    src = case.source.name if case.source is not None else case.name
    fig.text(0.06, 0.014, f"camdyn {ver} design review  \u00b7  {src}  \u00b7  {data.check.speed_rpm:g} rpm", size=7, color=C["grey"])
    fig.text(0.94, 0.014, f"page {number} of {total}", size=7, color=C["grey"], ha="right")


def _hline(fig, y: float, x0: float = 0.06, x1: float = 0.94, **kw):
    from matplotlib.lines import Line2D

    return Line2D([x0, x1], [y, y], transform=fig.transFigure, color=kw.pop("color", "#bbbbbb"), linewidth=kw.pop("lw", 0.8), **kw)


def _fmt(v, digits: int = 4) -> str:
    if v is None:
        return "unbounded"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float | int | np.floating):
        v = float(v)
        if not math.isfinite(v):
            return "unbounded"
        return f"{v:.{digits}g}"
    if isinstance(v, list | tuple):
        if len(v) > 4:
            return f"{len(v)} values"
        return "(" + ", ".join(_fmt(x) for x in v) + ")"
    return str(v)


class _Flow:
    """Top-down text layout on a figure (figure coordinates)."""

    def __init__(self, fig, y: float, left: float = 0.06, right: float = 0.94):
        self.fig, self.y, self.left, self.right = fig, y, left, right

    def h(self, size: float, lines: float = 1.0) -> float:
        return lines * size * 1.45 / 72.0 / self.fig.get_figheight()

    def heading(self, text: str) -> None:
        self.y -= self.h(10.5) * 0.6
        self.fig.text(self.left, self.y, text, size=10.5, weight="bold", va="top", color=C["ink"])
        self.y -= self.h(10.5)
        self.fig.add_artist(_hline(self.fig, self.y + self.h(10.5) * 0.12, self.left, self.right, color="#dddddd", lw=0.6))
        self.y -= self.h(10.5) * 0.15

    def row(self, cells: list[tuple[float, str, dict]], size: float = 8.0) -> None:
        """cells: (x as a fraction of the flow width, text, text kwargs)."""
        for x, text, kw in cells:
            self.fig.text(self.left + x * (self.right - self.left), self.y, text, **({"size": size, "va": "top"} | kw))
        self.y -= self.h(size)

    def para(self, text: str, size: float = 8.0, width: int = 118, indent: float = 0.0, **kw) -> None:
        lines = textwrap.wrap(text, width) or [""]
        self.fig.text(self.left + indent, self.y, "\n".join(lines), size=size, va="top", linespacing=1.3, **kw)
        self.y -= self.h(size, len(lines)) * 0.93


# -------------------------------------------------------------------------------- 1 summary
_CHECK_WHAT = {
    "contact_force": "least interface force, dynamic",
    "speed_margin": "dynamic jump speed / cam speed",
    "pressure_angle": "largest pressure angle",
    "curvature": "least contour radius / roller radius",
    "face_width": "contact travel along the face",
}

_UNITS = {
    "base_radius": "mm", "roller_radius": "mm", "offset": "mm", "pivot_distance": "mm", "pivot_angle": "deg",
    "arm_length": "mm", "face_width": "mm", "speed": "rpm", "mass": "kg", "spring_rate": "N/mm", "preload": "N",
    "train_stiffness": "N/mm", "external_force": "N", "inertia": "kg\u00b7m\u00b2", "torsion_rate": "N\u00b7m/rad",
    "preload_torque": "N\u00b7m", "train_torsion_rate": "N\u00b7m/rad", "external_torque": "N\u00b7m",
    "speed_margin": "\u00d7", "min_contact_force": "N", "max_pressure_angle": "deg",
}


def _margin(c) -> str:
    """The distance from the check's value to its limit, positive where it passes."""
    if c.value is None:
        return "\u221e" if c.ok else "-\u221e"
    d = c.value - c.limit if c.sense in (">=", ">") else c.limit - c.value
    if d == 0.0:
        return "0 (at the limit)"
    rel = f" ({100.0 * d / abs(c.limit):+.0f}%)" if abs(c.limit) > 1e-9 and abs(c.limit) < 1e9 else ""
    return f"{d:+.3g}{rel}"


def draw_summary(fig, data: ReportData) -> None:
    case, chk = data.case, data.check
    flow = _Flow(fig, 0.93)
    if case.spec.description:
        flow.para(case.spec.description, size=8.5, width=105, color=C["grey"])
    # the verdict, large
    passed = chk.verdict == "pass"
    flow.y -= flow.h(10)
    fig.text(
        flow.left + 0.012, flow.y, "PASS" if passed else "FAIL", size=26, weight="bold", va="top", color="white",
        bbox=dict(boxstyle="round,pad=0.35", fc=C["ok"] if passed else C["fail"], ec="none"),
    )
    n_fail = sum(not c.ok for c in chk.checks)
    dyn, kin = chk.dynamic, chk.kinematic
    what = "every check passes" if passed else f"{n_fail} of {len(chk.checks)} checks fail"
    model = f"{dyn['model']} follower" + (" (oscillating arm; torques as contact forces through the lever arm)" if data.oscillating else "")
    fig.text(flow.left + 0.2, flow.y + 0.002, f"at {chk.speed_rpm:g} rpm: {what}", size=12, va="top", weight="bold", color=C["ink"])
    fig.text(flow.left + 0.2, flow.y - flow.h(12), model, size=8.5, va="top", color=C["grey"])
    flow.y -= flow.h(26) * 1.35

    flow.heading("Checks")
    cols = [(0.0, "check"), (0.165, "what"), (0.6, "value"), (0.625, ""), (0.74, "limit"), (0.78, "margin"), (1.0, "result")]
    flow.row([(x, t, {"weight": "bold", "ha": "right" if t in ("value", "limit", "result") else "left", "color": C["grey"]}) for x, t in cols])
    for c in chk.checks:
        value = "unbounded" if c.value is None else f"{c.value:.4g}"
        ok_kw = {"color": C["ok"] if c.ok else C["fail"], "weight": "bold", "ha": "right"}
        flow.row(
            [
                (0.0, c.name, {"family": "DejaVu Sans Mono", "size": 7.8}),
                (0.165, _CHECK_WHAT.get(c.name, ""), {"color": C["grey"]}),
                (0.6, value, {"ha": "right"}),
                (0.625, {">=": "\u2265", "<=": "\u2264", ">": ">"}.get(c.sense, c.sense), {"ha": "center"}),
                (0.74, f"{c.limit:g} {c.unit}", {"ha": "right"}),
                (0.78, _margin(c), {"color": C["ok"] if c.ok else C["fail"]}),
                (1.0, "pass" if c.ok else "FAIL", ok_kw),
            ],
            size=8.5,
        )

    flow.heading("Key results")
    rows = [
        ("least force, dynamic", f"{dyn['min_contact_force_N']:.4g} N at {dyn['min_contact_force_deg']:.1f}\u00b0"),
        ("least force, kinematic", f"{kin['min_contact_force_N']:.4g} N at {kin['min_contact_force_deg']:.1f}\u00b0"),
        ("jump speed, dynamic", f"{_fmt(dyn['jump_speed_rpm'])} rpm"),
        ("jump speed, rigid", f"{_fmt(kin['jump_speed_rpm'])} rpm" + (f" (at {kin['jump_speed_at_deg']:.1f}\u00b0)" if kin["jump_speed_at_deg"] is not None else "")),
    ]
    seps = chk.response.separations
    if seps:
        spans = ", ".join(f"{s.start_deg:.0f}\u2013{s.end_deg:.0f}\u00b0" for s in seps[:2]) + (", \u2026" if len(seps) > 2 else "")
        gap = max(s.max_gap for s in seps) * data.to_display
        rows.append(("separations", f"{len(seps)}: {spans}; gap {gap:.3g} {data.unit}"))
    else:
        rows.append(("separations", "none"))
    rv = chk.response.residual_vibration * data.to_display
    rows.append(("residual vibration", f"{rv:.3g} {data.unit}"))
    geo = chk.geometry
    if geo is not None:
        rows.append(("max pressure angle", f"{geo.max_pressure_angle_deg:.2f}\u00b0 at {geo.max_pressure_angle_at_deg:.1f}\u00b0"))
        rows.append(("least radius of curvature", f"{geo.min_radius_of_curvature_mm:.4g} mm at {geo.min_radius_of_curvature_at_deg:.1f}\u00b0" + ("  (undercut)" if geo.undercut else "")))
    syn = case.synthesis
    if syn is not None:
        sm = syn.summary
        rows.append(("path error", f"{sm['max_path_error_mm']:.3g} mm"))
    half = (len(rows) + 1) // 2
    for i in range(half):
        cells = []
        for j, off in ((i, 0.0), (i + half, 0.5)):
            if j < len(rows):
                cells += [(off, rows[j][0], {"color": C["grey"]}), (off + 0.2, rows[j][1], {})]
        flow.row(cells, size=8.2)

    notes = [(w, "warning", C["warn"]) for w in chk.warnings] + [(a, "advice", C["advice"]) for a in chk.advice]
    flow.heading("Warnings and advice" if notes else "Warnings and advice: none")
    budget = 14  # lines
    for k, (text, kind, colour) in enumerate(notes):
        lines = textwrap.wrap(text, 112)
        if budget - len(lines) < 1 and k < len(notes) - 1:
            flow.para(f"\u2026 and {len(notes) - k} more: run camdyn check {case.source.name if case.source else ''}".rstrip(), size=7.8, color=C["grey"])
            break
        fig.text(flow.left, flow.y, kind, size=7.8, va="top", color=colour, weight="bold")
        flow.para(text, size=7.8, width=112, indent=0.075, color=C["ink"])
        budget -= len(lines)

    flow.heading("Key inputs")
    _draw_inputs(fig, data, flow)
    _glance(fig, data, flow.y - 0.02)


def _glance(fig, data: ReportData, top: float) -> None:
    """Thumbnails in the space left at the bottom of the summary: the cam and the interface force."""
    bottom = 0.065
    if top - bottom < 0.12:
        return
    h = min(top - bottom - 0.03, 0.26)
    y0 = top - 0.03 - h
    resp = data.check.response
    geo = data.check.geometry
    if geo is not None:
        from matplotlib.patches import Polygon

        ax = fig.add_axes([0.1, y0, 0.24, h])
        ax.set_aspect("equal", adjustable="datalim")
        ax.add_patch(Polygon(geo.contour.T, closed=True, fc=C["cam"], ec=C["ink"], lw=1.0))
        ax.plot(0, 0, "+", color=C["ink"], ms=7)
        _follower_glyph(ax, data, 0.0, colour=C["dyn"], lw=1.0)
        ax.autoscale_view()
        ax.set_title("cam at \u03b8 = 0", fontsize=8.5)
        ax.set_xlabel("x (mm)", fontsize=7)
        ax.set_ylabel("y (mm)", fontsize=7)
        ax.tick_params(labelsize=6.5)
        ax.grid(False)
    ax = fig.add_axes([0.42, y0, 0.52, h])
    ax.plot(resp.theta_deg, resp.kinematic_force, color=C["kin"], ls="--", lw=0.9, label="kinematic")
    ax.plot(resp.theta_deg, resp.force, color=C["dyn"], lw=1.2, label="dynamic")
    ax.axhline(0.0, color=C["ink"], lw=0.7)
    mf = data.case.limits.min_contact_force
    if mf:
        ax.axhline(mf, color=C["limit"], ls="--", lw=0.8, label="min_contact_force")
    _shade_separations(ax, resp, label=True)
    _deg_ticks(ax, 60.0)
    ax.set_title(f"interface force at {data.check.speed_rpm:g} rpm", fontsize=8.5)
    ax.set_xlabel("cam angle \u03b8 (deg)", fontsize=7)
    ax.set_ylabel("force (N)", fontsize=7)
    ax.tick_params(labelsize=6.5)
    ax.legend(loc="upper right", fontsize=6.5, ncol=4)
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + 0.2 * (hi - lo))


def _kv_lines(d: dict, oscillating: bool = False) -> list[tuple[str, str]]:
    out = []
    for k, v in d.items():
        unit = _UNITS.get(k, "")
        if k == "damping":
            unit = "N\u00b7m\u00b7s/rad" if oscillating else "N\u00b7s/m"
        out.append((k, f"{_fmt(v)} {unit}".strip()))
    return out


def _geom_unit(key: str, value) -> str:
    """Unit of a [path] or [mechanism] value (lengths mm, angles deg)."""
    if isinstance(value, bool | str) or "mode" in key or key in ("phase", "reverse"):
        return ""
    if isinstance(value, list | tuple) and len(value) > 4:
        return ""
    return "deg" if ("angle" in key or key == "rotation") else "mm"


def _draw_inputs(fig, data: ReportData, flow: _Flow) -> None:
    case = data.case
    spec = case.spec
    columns: list[tuple[str, list[tuple[str, str]]]] = []
    if spec.motion is not None:
        rows, start = [], 0.0
        lu = "deg" if data.oscillating else "mm"
        for seg in spec.motion.segments:
            lift = "" if seg.law == "dwell" else f"  {seg.lift:+g} {lu}"
            rows.append((f"{start:g}\u2013{seg.end:g}\u00b0", f"{seg.law}{lift}"))
            start = seg.end
        columns.append(("motion", rows))
        columns.append(("follower", _kv_lines(case.follower.model_dump(exclude_unset=True))))
    else:
        path = spec.path.model_dump(exclude_unset=True)
        columns.append(("path", [(k, f"{_fmt(v)} {_geom_unit(k, v)}".strip()) for k, v in path.items()]))
        mech = [(k, f"{_fmt(v)} {_geom_unit(k, v)}".strip()) for k, v in spec.mechanism.model_dump(exclude_unset=True).items()]
        sm = case.synthesis.summary
        mech += [("\u2192 crank", f"{sm['crank_mm']:.4g} mm"), ("\u2192 coupler", f"{sm['coupler_mm']:.4g} mm"), ("\u2192 base radius", f"{sm['base_radius_mm']:.4g} mm")]
        if "stroke_mm" in sm:
            mech.append(("\u2192 stroke", f"{sm['stroke_mm']:.4g} mm"))
        if "swing_deg" in sm:
            mech.append(("\u2192 swing", f"{sm['swing_deg']:.4g} deg"))
        mech.append(("\u2192 rotation", sm["rotation"]))
        columns.append(("mechanism (\u2192 synthesized)", mech))
    dyn_rows = _kv_lines(spec.dynamics.model_dump(exclude_unset=True), data.oscillating)
    lim = spec.limits.model_dump()
    pa = next((c.limit for c in data.check.checks if c.name == "pressure_angle"), None)
    if lim.get("max_pressure_angle") is None and pa is not None:
        lim["max_pressure_angle"] = pa
    dyn_rows += [("", ""), ("\x00limits", "")] + _kv_lines(lim)
    columns.append(("dynamics", dyn_rows))
    width = 1.0 / len(columns)
    y0 = flow.y
    ys = []
    for i, (title, rows) in enumerate(columns):
        flow.y = y0
        x = i * width
        flow.row([(x, title, {"weight": "bold", "color": C["grey"]})], size=8.2)
        key_w = max([len(k) for k, _ in rows if not k.startswith("\x00")] + [8]) * 0.0083 + 0.012  # flow units
        for k, v in rows[:26]:
            if k.startswith("\x00"):  # a sub-heading
                flow.row([(x, k[1:], {"weight": "bold", "color": C["grey"]})], size=8.2)
                continue
            flow.row([(x, k, {"color": C["grey"]}), (x + key_w, v, {})], size=7.6)
        if len(rows) > 26:
            flow.row([(x, f"\u2026 {len(rows) - 26} more", {"color": C["grey"]})], size=7.6)
        ys.append(flow.y)
    flow.y = min(ys)


# ----------------------------------------------------------------------------------- 2 svaj
def _mark_breaks(ax, data: ReportData) -> None:
    for b in data.case.motion.breaks_deg:
        ax.axvline(b, color=C["break"], lw=0.7, ls=":", zorder=0.5)


def draw_svaj(fig, data: ReportData) -> None:
    th, vals = data.svaj
    u = data.unit
    w = data.omega
    osc = data.oscillating
    sym = "\u03c8" if osc else "s"
    names = [
        (f"{'swing' if osc else 'lift'} {sym}", f"{u}"),
        (f"velocity d{sym}/d\u03b8", f"{u}/rad"),
        (f"acceleration d\u00b2{sym}/d\u03b8\u00b2", f"{u}/rad\u00b2"),
        (f"jerk d\u00b3{sym}/d\u03b8\u00b3", f"{u}/rad\u00b3"),
    ]
    # per-radian (left) -> time units at the case speed (right)
    if osc:
        right = [None, ("rad/s", math.pi / 180 * w), ("rad/s\u00b2", math.pi / 180 * w**2), ("rad/s\u00b3", math.pi / 180 * w**3)]
    else:
        right = [None, ("mm/s", w), ("m/s\u00b2", w**2 / 1000.0), ("m/s\u00b3", w**3 / 1000.0)]
    gs = fig.add_gridspec(4, 1, left=_LEFT, right=_RIGHT, top=0.885, bottom=0.12, hspace=0.12)
    axes = [fig.add_subplot(gs[0])]
    axes += [fig.add_subplot(gs[i], sharex=axes[0]) for i in range(1, 4)]
    jumps = data.jumps
    for i, ax in enumerate(axes):
        ax.plot(th, vals[i], color=C["dyn"], lw=1.3)
        ax.axhline(0.0, color="#888888", lw=0.6, zorder=0.6)
        _mark_breaks(ax, data)
        ax.set_ylabel(f"{names[i][0]}\n({names[i][1]})")
        if right[i] is not None:
            label, k = right[i]
            sec = ax.secondary_yaxis("right", functions=(lambda y, k=k: y * k, lambda y, k=k: y / k))
            sec.set_ylabel(f"at {data.check.speed_rpm:g} rpm ({label})", color=C["grey"])
            sec.tick_params(colors=C["grey"])
        if i < 3:
            ax.tick_params(labelbottom=False)
        lo, hi = float(np.min(vals[i])), float(np.max(vals[i]))
        pad = 0.12 * max(hi - lo, 1e-12)
        ax.set_ylim(lo - pad, hi + pad * (2.2 if i == 0 and getattr(data.case.motion, "segments", ()) else 1.0))
    _deg_ticks(axes[-1], 30.0)
    axes[-1].set_xlabel("cam angle \u03b8 (deg)")
    # time at the case speed along the top
    period_ms = 60000.0 / data.check.speed_rpm
    top = axes[0].secondary_xaxis("top", functions=(lambda d: d / 360.0 * period_ms, lambda t: t / period_ms * 360.0))
    top.set_xlabel(f"time at {data.check.speed_rpm:g} rpm (ms)", color=C["grey"])
    top.tick_params(colors=C["grey"])
    # segment laws along the lift curve
    segs = getattr(data.case.motion, "segments", ())
    ymax = axes[0].get_ylim()[1]
    for seg in segs:
        span = seg.end - seg.start
        if span >= 18.0:
            label = seg.law if span >= 40 else seg.law.replace("polynomial-", "poly-").replace("modified-", "mod-")
            axes[0].text(0.5 * (seg.start + seg.end), ymax, label, ha="center", va="top", size=7.2, color=C["grey"])
    # discontinuities: velocity jumps (infinite acceleration) and acceleration jumps (infinite jerk)
    flagged = bool(jumps)
    degs = sorted({d for d, _, _ in jumps})
    gaps = np.diff(degs + [degs[0] + 360.0]) if degs else np.array([360.0])
    compact = len(degs) > 4 or float(gaps.min()) < 50.0  # many or close: values only, listed in the note
    for k, (deg, order, jump) in enumerate(jumps):
        ax = axes[order]
        y_lo, y_hi = ax.get_ylim()
        at = (0.0, 360.0) if deg == 0.0 else (deg,)
        x_txt = deg + (2.5 if deg < 300 else -2.5)
        what = "velocity" if order == 1 else "acceleration"
        text = f"{jump:+.3g}" if compact else f"{what} jumps {jump:+.3g} {names[order][1]}"
        height = (0.9, 0.76, 0.62)[k % 3] if compact else 0.86
        ax.text(x_txt, y_lo + height * (y_hi - y_lo), text, size=7 if not compact else 6.5, color=C["limit"], ha="left" if deg < 300 else "right", va="center")
        for ax_k in axes[order:order + 2]:
            for a in at:
                ax_k.axvline(a, color=C["limit"], lw=1.1, alpha=0.5, zorder=0.7)
        if order + 1 < 4 and not compact:
            nxt = axes[order + 1]
            ny_lo, ny_hi = nxt.get_ylim()
            nxt.text(x_txt, ny_lo + 0.68 * (ny_hi - ny_lo), f"infinite {'acceleration' if order == 1 else 'jerk'}", size=7, color=C["limit"], ha="left" if deg < 300 else "right", va="center")
    if compact:
        for order in sorted({o for _, o, _ in jumps}):
            if order + 1 < 4:
                axes[order + 1].text(0.995, 0.96, f"red lines: infinite {'acceleration' if order == 1 else 'jerk'}", transform=axes[order + 1].transAxes, size=7, color=C["limit"], ha="right", va="top", bbox=dict(fc="white", ec="none", alpha=0.85, pad=0.8))
    what = "segment boundaries" if segs else "breaks of the path's curvature"
    if data.case.motion.breaks_deg:
        note = f"Dotted: {what}."
    else:
        note = "No segment boundaries: the motion is smooth all round."
    note += f" Right axes: the same curves in time units at {data.check.speed_rpm:g} rpm."
    if flagged:
        note += " Red: a velocity or acceleration jump at a boundary, and the infinite acceleration or jerk it causes."
        if compact:
            for order, what in ((1, "Velocity"), (2, "Acceleration")):
                listed = [f"{d:.1f}\u00b0 {j:+.3g}" for d, o, j in jumps if o == order]
                if listed:
                    note += f" {what} jumps ({names[order][1]}): " + ", ".join(listed) + "."
    elif data.case.motion.breaks_deg:
        note += f" Velocity and acceleration are continuous at every one of the {what}."
    if osc:
        note += " The swing is in degrees per radian of cam angle."
    fig.text(0.06, 0.068, "\n".join(textwrap.wrap(note, 128)[:4]), size=7.3, color=C["grey"], va="top", linespacing=1.25)


# ------------------------------------------------------------------------------------ 3 cam
def _rot(angle_rad: float, xy: np.ndarray) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s], [s, c]]) @ xy


def _follower_at(data: ReportData, theta_deg: float) -> dict:
    """The follower as the cam sees it at cam angle theta (cam frame, mm): roller centre (or face reference
    point), contact point, outward unit normal at the contact, and the unit direction in which the follower
    point at the contact moves for a positive lift."""
    geo, f = data.check.geometry, data.case.follower
    row = geo.table(np.array([theta_deg]))
    centre = np.array([row["pitch_x_mm"][0], row["pitch_y_mm"][0]])
    contact = np.array([row["contour_x_mm"][0], row["contour_y_mm"][0]])
    back = -f.sigma * math.radians(theta_deg)  # fixed frame -> cam frame
    d = 0.01
    tt = geo.table(np.array([theta_deg - d, theta_deg + d]))
    tan = np.array([tt["contour_x_mm"][1] - tt["contour_x_mm"][0], tt["contour_y_mm"][1] - tt["contour_y_mm"][0]])
    normal = np.array([tan[1], -tan[0]]) / max(np.linalg.norm(tan), 1e-300)
    if normal @ contact < 0:  # outward
        normal = -normal
    if f.translating:
        move = _rot(back, np.array([0.0, 1.0]))
        pivot = None
    else:
        pa = math.radians(f.pivot_angle)
        pivot = _rot(back, f.pivot_distance * np.array([math.cos(pa), math.sin(pa)]))
        arm = contact - pivot
        move = np.array([-arm[1], arm[0]]) / np.linalg.norm(arm)
    if move @ normal < 0:
        move = -move
    return {"centre": centre, "contact": contact, "normal": normal, "move": move, "pivot": pivot, "back": back}


def _follower_glyph(ax, data: ReportData, theta_deg: float, *, colour, lw=1.0, alpha=1.0, stem=True, z=3) -> dict:
    """Draw the follower as the cam sees it at cam angle theta (cam frame); returns :func:`_follower_at`."""
    from matplotlib.patches import Circle

    f = data.case.follower
    at = _follower_at(data, theta_deg)
    centre, contact = at["centre"], at["contact"]
    stem_len = 1.6 * (f.roller_radius or 0.15 * f.base_radius)
    if f.roller:
        ax.add_patch(Circle(centre, f.roller_radius, fill=False, ec=colour, lw=lw, alpha=alpha, zorder=z))
        ax.plot(*centre, marker=".", ms=2.5, color=colour, alpha=alpha, zorder=z)
        base = centre
    else:
        along = np.array([-at["normal"][1], at["normal"][0]])
        half = 0.5 * (f.face_width or max(2.0 * abs((contact - centre) @ along), 0.3 * f.base_radius)) + 2.0
        mid = contact - along * ((contact - centre) @ along)
        a, b = mid - along * half, mid + along * half
        ax.plot([a[0], b[0]], [a[1], b[1]], color=colour, lw=lw * 2.0, alpha=alpha, zorder=z, solid_capstyle="butt")
        base = mid
    tip = base
    if stem:
        if at["pivot"] is None:
            tip = base + at["move"] * stem_len
        else:
            d = at["pivot"] - base
            tip = base + d / np.linalg.norm(d) * min(np.linalg.norm(d), stem_len)
        ax.plot([base[0], tip[0]], [base[1], tip[1]], color=colour, lw=lw * 1.6, alpha=alpha, zorder=z, solid_capstyle="butt")
    at["tip"] = tip
    return at


def _check_of(data: ReportData, name: str):
    return next((c for c in data.check.checks if c.name == name), None)


def draw_cam(fig, data: ReportData) -> None:
    from matplotlib.patches import Circle, FancyArrowPatch, Polygon

    geo, f, lim = data.check.geometry, data.case.follower, data.case.limits
    ax = fig.add_axes([0.08, 0.43, 0.84, 0.455])
    ax.set_aspect("equal")
    ax.grid(False)
    contour, pitch = geo.contour, geo.pitch
    ax.add_patch(Polygon(contour.T, closed=True, fc=C["cam"], ec=C["ink"], lw=1.3, zorder=1, label="cam contour"))
    if f.roller:
        ax.plot(*np.c_[pitch, pitch[:, :1]], color=C["dyn"], lw=0.9, ls="--", zorder=2, label="pitch curve (roller centre)")
    ax.add_patch(Circle((0, 0), f.base_radius, fill=False, ec=C["grey"], lw=0.8, ls=":", zorder=2, label=f"base circle, radius {f.base_radius:.4g} mm"))
    ax.plot(0, 0, marker="+", color=C["ink"], ms=9, mew=1.2, zorder=4)
    r_all = np.hypot(pitch[0], pitch[1]).max() + (f.roller_radius or 0.0)
    # the follower as the cam sees it at a few angles
    reach = r_all
    for th in (0.0, 90.0, 180.0, 270.0):
        at = _follower_glyph(ax, data, th, colour=C["grey"], lw=0.9, alpha=0.85, z=3)
        reach = max(reach, float(np.max(np.abs(at["tip"]))) + 0.1 * r_all)
        out = at["tip"] - at["centre"]
        out = out / np.linalg.norm(out) if np.linalg.norm(out) > 1e-9 else at["centre"] / max(np.linalg.norm(at["centre"]), 1e-9)
        ax.annotate(f"{th:g}\u00b0", at["tip"], xytext=tuple(9 * out), textcoords="offset points", size=7.5, color=C["grey"], ha="center", va="center", zorder=5)
    # the worst pressure angle: the follower there, its direction of motion and the contact normal
    th_pa = geo.max_pressure_angle_at_deg
    c_pa = _check_of(data, "pressure_angle")
    col_pa = C["margin"] if (c_pa is None or c_pa.ok) else C["fail"]
    at = _follower_glyph(ax, data, th_pa, colour=col_pa, lw=1.6, z=6, stem=False)
    L = 0.32 * r_all
    origin = at["centre"] if f.roller else at["contact"]
    arrows = ((at["normal"], at["move"], "contact normal"), (at["move"], at["normal"], "follower motion"))
    for vec, other, text in arrows:
        ax.add_patch(FancyArrowPatch(origin, origin + vec * L, arrowstyle="-|>", mutation_scale=9, color=col_pa, lw=1.2, zorder=6))
        side = np.array([-vec[1], vec[0]])
        if side @ other > 0:
            side = -side
        ax.annotate(text, origin + vec * L, xytext=tuple(8 * side), textcoords="offset points", size=7, color=col_pa, ha="left" if side[0] > 0 else "right", va="center", zorder=6)
    fig.text(
        0.08, 0.922, f"\u25cf max pressure angle {geo.max_pressure_angle_deg:.1f}\u00b0 at \u03b8 = {th_pa:.1f}\u00b0: the follower there, "
        "its motion and the contact normal", size=7.8, color=col_pa, va="top",
    )
    # least radius of curvature: the osculating circle on the contour
    th_r = geo.min_radius_of_curvature_at_deg
    rho = geo.min_radius_of_curvature_mm
    c_r = _check_of(data, "curvature")
    col_r = C["advice"] if (c_r is None or c_r.ok) else C["fail"]
    at_r = _follower_at(data, th_r)
    p = at_r["contact"]
    if math.isfinite(rho):
        if abs(rho) < 3 * r_all:
            ax.add_patch(Circle(p - at_r["normal"] * rho, abs(rho), fill=False, ec=col_r, lw=0.9, ls="--", zorder=5))
        ax.plot(*p, marker="o", ms=5, color=col_r, zorder=7)
        fig.text(0.08, 0.906, f"\u25cf least radius of curvature {rho:.3g} mm at \u03b8 = {th_r:.1f}\u00b0: the point on the contour and its osculating circle (dashed)", size=7.8, color=col_r, va="top")
    # sense of rotation
    arc_r = 0.22 * f.base_radius
    sign = f.sigma
    a0, a1 = (math.radians(200), math.radians(340)) if sign > 0 else (math.radians(340), math.radians(200))
    ax.add_patch(FancyArrowPatch((arc_r * math.cos(a0), arc_r * math.sin(a0)), (arc_r * math.cos(a1), arc_r * math.sin(a1)), connectionstyle=f"arc3,rad={0.5 * sign}", arrowstyle="-|>", mutation_scale=8, color=C["ink"], lw=0.9, zorder=4))
    ax.text(0, -arc_r * 1.9, f"turns {f.rotation}", size=7.5, ha="center", va="center", color=C["ink"])
    lim_r = max(reach, float(np.max(np.abs(origin))) + L * 1.25) * 1.06
    ax.set_xlim(-lim_r, lim_r)
    ax.set_ylim(-lim_r, lim_r)
    ax.set_xlabel("x, cam frame = fixed frame at \u03b8 = 0 (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(loc="lower left", fontsize=7, framealpha=0.9)
    fig.text(0.08, 0.94, f"cam and {f.type.replace('-', ' ')} follower; grey: the follower as the cam sees it at 0, 90, 180, 270\u00b0", size=9, weight="bold", va="top")

    # pressure angle and radius of curvature against the cam angle
    gs = fig.add_gridspec(2, 1, left=_LEFT, right=0.95, top=0.37, bottom=0.06, hspace=0.35)
    ax1 = fig.add_subplot(gs[0])
    ax2 = fig.add_subplot(gs[1], sharex=ax1)
    th = geo.theta_deg
    pa = geo.pressure_angle_deg
    pa_lim = next((c.limit for c in data.check.checks if c.name == "pressure_angle"), None)
    ax1.plot(th, pa, color=C["dyn"], lw=1.3, label="pressure angle")
    if pa_lim is not None:
        for sgn in (1, -1):
            ax1.axhline(sgn * pa_lim, color=C["limit"], ls="--", lw=0.9)
        top = max(pa_lim, np.abs(pa).max()) * 1.18
        ax1.axhspan(pa_lim, top, color=C["limit"], alpha=0.08, lw=0)
        ax1.axhspan(-top, -pa_lim, color=C["limit"], alpha=0.08, lw=0)
        ax1.set_ylim(-top, top)
        ax1.text(2, pa_lim, f" limit \u00b1{pa_lim:g}\u00b0", color=C["limit"], size=7, va="bottom")
    i = int(np.argmax(np.abs(pa)))
    ax1.plot(th[i], pa[i], "o", color=col_pa, ms=4.5)
    ax1.axhline(0, color="#888888", lw=0.6)
    _mark_breaks(ax1, data)
    ax1.set_ylabel("pressure angle (deg)")
    ax1.set_title("pressure angle", fontsize=9)
    ax1.tick_params(labelbottom=False)

    rho_c = geo.rho_contour_mm.copy()
    cap = max(3.0 * f.base_radius, 2.5 * ((f.roller_radius or 0.0) * lim.min_curvature_ratio))
    finite = np.isfinite(rho_c)
    low = float(np.min(rho_c[finite])) if finite.any() else -cap
    floor = max(low, -cap)
    shown = np.where(finite & (np.abs(rho_c) <= cap * 1.05), rho_c, np.nan)
    ax2.plot(th, shown, color=C["dyn"], lw=1.3, label="contour")
    if f.roller:
        rho_p = np.where(np.abs(geo.rho_pitch_mm) <= cap * 1.05, geo.rho_pitch_mm, np.nan)
        ax2.plot(th, rho_p, color=C["dyn"], lw=0.8, ls="--", alpha=0.7, label="pitch curve")
        r_lim = lim.min_curvature_ratio * f.roller_radius
        ax2.axhline(r_lim, color=C["limit"], ls="--", lw=0.9)
        ax2.text(2, r_lim, f" limit {lim.min_curvature_ratio:g} \u00d7 roller radius = {r_lim:.3g} mm (convex)", color=C["limit"], size=7, va="bottom")
    else:
        ax2.axhline(0.0, color=C["limit"], ls="--", lw=0.9)
        ax2.text(2, 0.0, " limit: no cusp (\u03c1 > 0)", color=C["limit"], size=7, va="bottom")
    ax2.axhline(0, color="#888888", lw=0.6)
    ax2.plot(th_r, rho, "o", color=col_r, ms=4.5)
    ax2.set_ylim(min(floor * 1.1, -0.05 * cap), cap)
    _mark_breaks(ax2, data)
    ax2.set_ylabel("radius of curvature (mm)")
    ax2.set_title(f"radius of curvature (convex > 0; |\u03c1| above {cap:.0f} mm not drawn)", fontsize=9)
    ax2.legend(loc="upper right", fontsize=7, ncol=2)
    _deg_ticks(ax2, 30.0)
    ax2.set_xlabel("cam angle \u03b8 (deg)")


# ------------------------------------------------------------------------------- 4 dynamics
def _shade_separations(ax, resp, label: bool = False) -> None:
    first = True
    for s in resp.separations:
        spans = [(s.start_deg, s.end_deg)] if s.end_deg >= s.start_deg else [(s.start_deg, 360.0), (0.0, s.end_deg)]
        for a, b in spans:
            ax.axvspan(a, b, color=C["limit"], alpha=0.13, lw=0, zorder=0.4, label="separated" if (label and first) else None)
            first = False


def _force_panel(ax, data: ReportData, resp, rpm: float, colour: str, title: str) -> None:
    th = resp.theta_deg
    ax.plot(th, resp.kinematic_force, color=C["kin"], lw=1.0, ls="--", label="kinematic (rigid, never leaves)")
    ax.plot(th, resp.force, color=colour, lw=1.3, label=f"dynamic ({resp.model})")
    ax.axhline(0.0, color=C["ink"], lw=0.8)
    _shade_separations(ax, resp, label=True)
    _mark_breaks(ax, data)
    i = int(np.argmin(resp.force))
    ax.plot(th[i], resp.force[i], "o", color=colour, ms=4)
    right = th[i] < 250.0
    ax.annotate(f"least {resp.force[i]:.3g} N at {th[i]:.1f}\u00b0", xy=(th[i], resp.force[i]), xytext=(6 if right else -6, -5), textcoords="offset points", size=7, color=colour, va="top", ha="left" if right else "right")
    ax.set_ylabel("interface force (N)")
    ax.set_title(title, fontsize=9)
    ax.legend(loc="upper right", fontsize=7, ncol=3)


def draw_dynamics(fig, data: ReportData) -> None:
    chk = data.check
    resp = chk.response
    rpm = chk.speed_rpm
    mresp = data.margin_response
    gs = fig.add_gridspec(5, 1, left=_LEFT, right=0.95, top=0.925, bottom=0.06, hspace=0.38)
    ax_f = fig.add_subplot(gs[0])
    ax_m = fig.add_subplot(gs[1], sharex=ax_f)
    ax_x = fig.add_subplot(gs[2], sharex=ax_f)
    ax_v = fig.add_subplot(gs[3], sharex=ax_f)
    ax_w = fig.add_subplot(gs[4])
    osc = " (contact force: torque / lever arm)" if data.oscillating else ""
    _force_panel(ax_f, data, resp, rpm, C["dyn"], f"interface force at {rpm:g} rpm{osc}")
    m = data.case.limits.speed_margin
    if isinstance(mresp, str):
        ax_m.text(0.5, 0.5, f"no steady state at {data.margin_rpm:g} rpm:\n{mresp}", transform=ax_m.transAxes, ha="center", va="center", color=C["fail"], size=8, wrap=True)
        ax_m.set_title(f"interface force at {m:g} \u00d7 speed = {data.margin_rpm:g} rpm", fontsize=9)
        ax_m.set_yticks([])
        ax_m.grid(False)
    else:
        _force_panel(ax_m, data, mresp, data.margin_rpm, C["margin"], f"interface force at speed_margin {m:g} \u00d7 speed = {data.margin_rpm:g} rpm")
        lo = min(ax_f.get_ylim()[0], ax_m.get_ylim()[0])
        hi = max(ax_f.get_ylim()[1], ax_m.get_ylim()[1])
        hi += 0.22 * (hi - lo)  # headroom for the legend
        ax_f.set_ylim(lo, hi)
        ax_m.set_ylim(lo, hi)
    for ax in (ax_f, ax_m, ax_x):
        ax.tick_params(labelbottom=False)
    # displacement, dynamic against kinematic
    k = data.to_display
    ax_x.plot(resp.theta_deg, resp.s * k, color=C["kin"], ls="--", lw=1.0, label="kinematic s (cam)")
    ax_x.plot(resp.theta_deg, resp.x * k, color=C["dyn"], lw=1.2, label=f"follower x at {rpm:g} rpm")
    _shade_separations(ax_x, resp)
    _mark_breaks(ax_x, data)
    ax_x.set_ylabel(f"{'swing' if data.oscillating else 'displacement'} ({data.unit})")
    ax_x.set_title("follower displacement, dynamic and kinematic", fontsize=9)
    ax_x.legend(loc="upper right", fontsize=7, ncol=2)
    # vibratory response x - s
    curves = [(resp, C["dyn"], f"{rpm:g} rpm")]
    if not isinstance(mresp, str):
        curves.append((mresp, C["margin"], f"{data.margin_rpm:g} rpm"))
    peak = max(float(np.max(np.abs(r.x - r.s))) for r, _, _ in curves) * k
    if data.oscillating:
        scale, vu = k, "deg"
    else:
        scale, vu = (1000.0, "\u00b5m") if peak < 0.5 else (1.0, "mm")
    for r, col, lab in curves:
        ax_v.plot(r.theta_deg, (r.x - r.s) * (scale if not data.oscillating else k), color=col, lw=1.1, label=lab)
    if peak == 0.0:
        ax_v.text(0.5, 0.6, "rigid follower in contact all round: x = s, no vibratory response", transform=ax_v.transAxes, ha="center", va="center", size=8, color=C["grey"])
    ax_v.axhline(0.0, color=C["ink"], lw=0.6)
    _shade_separations(ax_v, resp, label=True)
    _mark_breaks(ax_v, data)
    ax_v.set_ylabel(f"x \u2212 s ({vu})")
    ax_v.set_title("vibratory response x \u2212 s (negative: the train is compressed)", fontsize=9)
    ax_v.legend(loc="upper right", fontsize=7, ncol=2)
    _deg_ticks(ax_v, 30.0)
    ax_v.set_xlabel("cam angle \u03b8 (deg)")
    _speed_panel(ax_w, data)


def _speed_panel(ax, data: ReportData) -> None:
    sw = data.speed_sweep
    chk = data.check
    rpm = chk.speed_rpm
    v = sw["rpm"]
    ax.plot(v, sw["kinematic"], color=C["kin"], ls="--", lw=1.0, label="kinematic (rigid)")
    jd, jk = chk.dynamic["jump_speed_rpm"], chk.kinematic["jump_speed_rpm"]
    if sw["linear"] is not None:
        lin = sw["linear"]
        ok = v <= (jd if jd is not None else np.inf)
        ax.plot(v[ok], lin[ok], color=C["dyn"], lw=1.4, label="dynamic steady state (exact until separation)")
        if (~ok).any():
            ax.plot(v[~ok], lin[~ok], color=C["dyn"], lw=0.9, ls=":", alpha=0.7, label="linear model past the jump (not valid)")
    ax.axhline(0.0, color=C["ink"], lw=0.8)
    mf = chk.case.limits.min_contact_force
    if mf:
        ax.axhline(mf, color=C["limit"], ls="--", lw=0.8)
        ax.text(v[-1], mf, f"min_contact_force {mf:g} N ", color=C["limit"], size=7, ha="right", va="bottom")
    top = max(float(np.max(sw["kinematic"])), mf) * 1.15
    floor = min(float(np.min(sw["kinematic"])), float(np.min(sw["linear"])) if sw["linear"] is not None else 0.0)
    ymin, ymax = max(floor, -0.8 * top) - 0.05 * top, top
    if jd is not None and jd <= v[-1]:
        ax.axvspan(jd, v[-1], color=C["limit"], alpha=0.08, lw=0)
        ax.axvline(jd, color=C["limit"], lw=1.0)
        late = jd > 0.75 * v[-1]
        ax.text(jd, ymax, f" jump speed {jd:.0f} rpm " if late else f" jump speed {jd:.0f} rpm", color=C["limit"], size=7.5, va="top", ha="right" if late else "left")
    if jk is not None and jk <= v[-1] and (jd is None or abs(jk - jd) > 0.02 * v[-1]):
        ax.axvline(jk, color=C["kin"], lw=0.8, ls="--")
        ax.text(jk, ymin + 0.68 * (ymax - ymin), f"rigid {jk:.0f} rpm", color=C["kin"], size=7, va="center", ha="left", rotation=90, bbox=dict(fc="white", ec="none", alpha=0.85, pad=0.8))
    ax.axvline(data.margin_rpm, color=C["margin"], lw=0.9, ls="-.")
    ax.text(data.margin_rpm, ymin + 0.68 * (ymax - ymin), f"{data.case.limits.speed_margin:g} \u00d7 speed", color=C["margin"], size=7, va="center", ha="right", rotation=90, bbox=dict(fc="white", ec="none", alpha=0.85, pad=0.8))
    ax.plot(rpm, chk.dynamic["min_contact_force_N"], "o", color=C["dyn"] if chk.verdict == "pass" else C["fail"], ms=6, zorder=5, label=f"operating point ({rpm:g} rpm, time domain)")
    ax.set_ylim(ymin, ymax)
    ax.set_xlim(0.0, v[-1])
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel("least interface force (N)")
    ax.set_title("least interface force against cam speed", fontsize=9)
    ax.legend(loc="lower left", fontsize=7)


# ------------------------------------------------------------------------------ 5 mechanism
_LINKS = {
    "ccm": [("A", "B"), ("B", "T"), ("B", "C"), ("C", "E")],
    "oscillating": [("O", "A"), ("A", "B"), ("F", "C"), ("C", "D"), ("D", "E")],
}
_GROUND = {"ccm": ("A",), "oscillating": ("O", "D")}


def _mechanism_frames(data: ReportData, angles: np.ndarray) -> dict:
    syn = data.case.synthesis
    pts = syn.linkage_at(angles)
    sense = 1.0 if syn.summary["rotation"] == "ccw" else -1.0
    c0 = np.asarray(syn.mechanism.cam_center, dtype=float)
    idx = np.round(np.asarray(angles)).astype(int) % 360
    roller = np.stack([_rot(sense * math.radians(a), syn.pitch[i]) for a, i in zip(angles, idx)]) + c0
    cams = [(_rot(sense * math.radians(a), syn.contour.T)).T + c0 for a in angles]
    return {"points": pts, "roller": roller, "cams": cams, "c0": c0, "sense": sense}


def draw_mechanism(fig, data: ReportData) -> None:
    from matplotlib.patches import Circle, Polygon

    syn = data.case.synthesis
    kind = syn.mechanism.type
    angles = np.arange(0.0, 360.0, 60.0)
    fr = _mechanism_frames(data, angles)
    pts = fr["points"]
    rr = syn.mechanism.roller_radius
    target, traced = syn.path_xy, syn.traced_xy
    # common limits: every joint over a revolution, the cams and the path
    every = syn.linkage_at(np.arange(0.0, 360.0, 5.0))
    allxy = np.vstack([v for v in every.values()] + [target] + fr["cams"] + [fr["roller"] + rr, fr["roller"] - rr])
    lo, hi = allxy.min(axis=0), allxy.max(axis=0)
    pad = 0.06 * (hi - lo).max()
    lo, hi = lo - pad, hi + pad
    ncols = 3
    nrows = len(angles) // ncols
    # rows as tall as the drawings (equal aspect), the rest of the page to the path plots
    width_in = (0.89 * A4[0] - 2 * 0.6) / ncols
    height_in = min(width_in * (hi - lo)[1] / (hi - lo)[0], 2.7)
    grid_bottom = 0.895 - (nrows * height_in + (nrows - 1) * 0.45) / A4[1]
    gs = fig.add_gridspec(nrows, ncols, left=0.08, right=0.97, top=0.895, bottom=grid_bottom, hspace=0.45 / height_in, wspace=0.22)
    names = {"ccm": "A cam centre and crank, B crank pin, T tracing point, C coupler joint, E slider pin",
             "oscillating": "O cam centre, A crank pin, B coupler pin, F tracing point, C follower joint, D arm pivot, E roller"}
    caption = f"The linkage at six cam angles. {names[kind]}; \u25b2 fixed pivots; red: the tracing point on the target path (light blue)" + (
        "; grey bar: the slider, from its roller to E." if kind == "ccm" else "."
    )
    fig.text(0.06, 0.94, "\n".join(textwrap.wrap(caption, 140)), size=7.5, color=C["grey"], va="top", linespacing=1.3)
    for k, a in enumerate(angles):
        ax = fig.add_subplot(gs[k // ncols, k % ncols])
        ax.set_aspect("equal")
        ax.grid(False)
        ax.plot(*target.T, color=C["path"], lw=2.5, zorder=1)
        ax.add_patch(Polygon(fr["cams"][k], closed=True, fc=C["cam"], ec=C["ink"], lw=0.8, zorder=2))
        if kind == "ccm":
            e_dir = np.array([math.cos(math.radians(syn.mechanism.slider_angle)), math.sin(math.radians(syn.mechanism.slider_angle))])
            sp = np.asarray(syn.mechanism.slider_point if syn.mechanism.slider_point is not None else syn.mechanism.cam_center, dtype=float)
            span = (hi - lo).max() * 1.5
            ax.plot(*np.c_[sp - e_dir * span, sp + e_dir * span], color=C["grey"], lw=0.7, ls="-.", zorder=1)
            r, e = fr["roller"][k], pts["E"][k]
            ax.plot([r[0], e[0]], [r[1], e[1]], color=C["ink"], lw=3.0, alpha=0.6, zorder=3, solid_capstyle="butt")
        ax.add_patch(Circle(fr["roller"][k], rr, fc="white", ec=C["ink"], lw=1.0, zorder=4))
        for p, q in _LINKS[kind]:
            if p in pts and q in pts and np.linalg.norm(pts[p][k] - pts[q][k]) > 1e-9:
                ax.plot([pts[p][k][0], pts[q][k][0]], [pts[p][k][1], pts[q][k][1]], color=C["dyn"], lw=1.8, zorder=5, solid_capstyle="round")
        for name, xy in pts.items():
            ax.plot(*xy[k], "o", ms=3.2, mfc="white", mec=C["dyn"], mew=1.0, zorder=6)
        for g in _GROUND[kind]:
            ax.plot(*pts[g][k], marker="^", ms=8, color=C["ink"], zorder=6, ls="none")
        tip = "T" if kind == "ccm" else "F"
        ax.plot(*pts[tip][k], "o", ms=5, color=C["traced"], zorder=7)
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_title(f"\u03b8 = {a:g}\u00b0", fontsize=8.5)
        ax.tick_params(labelsize=6.5)
        if k == 0:
            centre = np.mean([xy[0] for xy in pts.values()], axis=0)
            labels: list[tuple[str, np.ndarray]] = []
            for name, xy in pts.items():  # one label per place: joints that coincide share it
                same = next((i for i, (_, q) in enumerate(labels) if np.linalg.norm(q - xy[0]) < 1e-6 * (hi - lo).max()), None)
                if same is None:
                    labels.append((name, xy[0]))
                else:
                    labels[same] = (f"{labels[same][0]}={name}", labels[same][1])
            for name, xy in labels:
                d = xy - centre
                d = d / np.linalg.norm(d) if np.linalg.norm(d) > 1e-9 else np.array([1.0, 0.0])
                ax.annotate(name, xy, xytext=tuple(9 * d), textcoords="offset points", size=7, weight="bold", color=C["ink"], ha="center", va="center", zorder=8)
        if k % ncols == 0:
            ax.set_ylabel("y (mm)", fontsize=7.5)
        if k >= len(angles) - ncols:
            ax.set_xlabel("x (mm)", fontsize=7.5)
    # target and traced path, and the error along it
    plot_h = min(grid_bottom - 0.13, 0.36)
    ax_p = fig.add_axes([0.08, 0.065, 0.38, plot_h])
    ax_p.set_aspect("equal", adjustable="datalim")
    ax_p.plot(*np.c_[target.T, target[:1].T], color=C["path"], lw=4.0, label="target path")
    ax_p.plot(*np.c_[traced.T, traced[:1].T], color=C["traced"], lw=1.0, ls="--", label="traced by the linkage")
    for a in range(0, 360, 45):
        ax_p.plot(*target[a], "o", ms=3, color=C["ink"])
        first = a < 180  # out and back along the same points (a line): first half above, second below
        ax_p.annotate(f"{a}\u00b0", target[a], xytext=(3, 3) if first else (3, -3), textcoords="offset points", size=6.5, color=C["grey"], va="bottom" if first else "top")
    ax_p.set_xlabel("x (mm)")
    ax_p.set_ylabel("y (mm)")
    ax_p.set_title("path: target and traced (cam angles marked)", fontsize=9)
    ax_p.legend(loc="best", fontsize=7)
    ax_e = fig.add_axes([0.58, 0.065, 0.38, plot_h])
    seg = np.linalg.norm(np.diff(np.vstack([target, target[:1]]), axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
    err = np.linalg.norm(traced - target, axis=1)
    ax_e.semilogy(arc, np.maximum(err, 1e-16), color=C["traced"], lw=1.0)
    ax_e.axhline(1e-3, color=C["limit"], ls="--", lw=0.8)
    ax_e.text(arc[-1], 1e-3, "1 \u00b5m ", color=C["limit"], size=7, ha="right", va="bottom")
    ax_e.set_ylim(1e-16, 1e-1)
    ax_e.set_xlim(0.0, arc[-1])
    ax_e.set_xlabel("distance along the target path (mm)")
    ax_e.set_ylabel("|traced \u2212 target| (mm)")
    ax_e.set_title(f"path error (largest {err.max():.2g} mm)", fontsize=9)


# --------------------------------------------------------------------------- 6 spring sizing
def _u(unit: str) -> str:
    """A unit as camdyn's text output writes it (N*m/rad) as this report prints it (N\u00b7m/rad)."""
    return unit.replace("*", "\u00b7")


def _small(x: float, scale: float) -> str:
    """``x`` to 4 digits, and 0 where it is round-off against ``scale`` (a zero rate from the LP: 1e-17)."""
    return _fmt(0.0 if abs(x) <= 1e-9 * max(1.0, abs(scale)) else x)


_DASH = "\u2013"


def _jump(rpm: float) -> str:
    return "unbounded" if not math.isfinite(rpm) else f"{rpm:.1f} rpm"


def draw_springs(fig, data: ReportData) -> None:
    sz = data.sizing
    flow = _Flow(fig, 0.94)
    if isinstance(sz, str):
        flow.para("Spring sizing does not apply to this case:", size=9, weight="bold", color=C["fail"])
        flow.para(sz, size=8.5, width=110, color=C["ink"])
        _spring_jump_map(fig, data)
        return
    u = {k: _u(v) for k, v in sz.units.items()}
    osc = sz.oscillating
    force = "torque" if osc else "force"
    k_sym, f_sym = ("k", "T0") if osc else ("k", "F0")
    nb = lambda text: text.replace(" ", "\u00a0")  # noqa: E731  (a formula is not broken across lines)
    constraint = nb(f"{f_sym} \u2265 r \u2212 {k_sym} s")
    caption = (
        f"The return spring with the least peak spring {force} {nb(f'P = {k_sym} s_max + {f_sym}')} that keeps the contact force \u2265 "
        f"min_contact_force = {sz.min_contact_force:g} N at every cam angle and every speed up to {sz.top_speed_rpm:.4g} rpm "
        f"(speed_margin {sz.margin:g} \u00d7 {sz.speed_rpm:g} rpm), {sz.model} follower. Each grey line is one cam angle's "
        f"constraint {constraint} (shown: the envelope and the binding angles); the springs above all of them hold."
    )
    fig.text(0.06, 0.94, "\n".join(textwrap.wrap(caption, 140)), size=7.5, color=C["grey"], va="top", linespacing=1.3)

    from ..plot import plot_feasible_region

    ax = fig.add_axes([_LEFT, 0.615, 0.95 - _LEFT, 0.26])
    plot_feasible_region(ax, sz, colors={"kinematic": C["kin"], "dynamic": C["dyn"], "lines": C["constraint"], "iso": C["iso"], "chosen": C["ok"], "current": C["ink"]})
    if osc:
        ax.set_xlabel(f"torsion rate k ({u['rate']})")
        ax.set_ylabel(f"preload torque T0 ({u['preload']})")
    else:
        ax.set_xlabel(f"spring rate k ({u['rate']})")
        ax.set_ylabel(f"preload F0 ({u['preload']})")
    ax.set_title(f"feasible springs: preload against rate (holding up to {sz.top_speed_rpm:.4g} rpm)", fontsize=9)
    for t in ax.texts:  # the iso-line labels, in this report's way of writing units
        t.set_text(_u(t.get_text()))
    for line in ax.lines:  # a spring at the least rate (often 0) sits on the left edge: draw it whole
        if line.get_marker() not in (None, "None", ""):
            line.set_clip_on(False)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=4, fontsize=7)

    # the springs compared
    flow = _Flow(fig, 0.545)
    flow.heading("Springs compared")
    designs = [("chosen", sz.chosen)] + ([("kinematic LP\nanswer", sz.kinematic)] if sz.model == "compliant" else [])
    designs += [("current\ndesign", sz.current), ("current rate,\nleast preload", sz.at_current_rate)]
    xs = [0.52, 0.67, 0.82, 0.97] if len(designs) == 4 else [0.57, 0.77, 0.97]
    head = [(0.0, f"forces over every angle and\nevery speed up to {sz.top_speed_rpm:.4g} rpm", {"color": C["grey"], "linespacing": 1.3})]
    head += [(x, name, {"weight": "bold", "ha": "right", "linespacing": 1.3, "color": C["ok"] if name == "chosen" else C["grey"]}) for x, (name, _) in zip(xs, designs)]
    flow.row(head, size=8.2)
    flow.y -= flow.h(8.2) * 1.05
    holds = [d.least_force >= sz.min_contact_force - 1e-6 * max(1.0, abs(d.peak_contact)) for _, d in designs]
    rows = [
        (f"{'torsion' if osc else 'spring'} rate {k_sym} ({u['rate']})", [_small(d.rate, d.peak_spring / max(sz.s_max, 1e-300)) for _, d in designs]),
        (f"preload {f_sym} ({u['preload']})", [_small(d.preload, d.peak_spring) for _, d in designs]),
        (f"peak spring {force} P ({u['spring']})", [_fmt(d.peak_spring) for _, d in designs]),
        # a design that misses the limit by less than 4 digits shows the digits it misses by
        ("least contact force (N)", [_small(d.least_force, d.peak_contact) if h else f"{d.least_force:.7g}" for (_, d), h in zip(designs, holds)]),
        ("peak contact force (N)", [_fmt(d.peak_contact) for _, d in designs]),
        ("jump speed, kinematic (rigid)", [_jump(d.kinematic_jump_rpm) for _, d in designs]),
        ("jump speed, dynamic", [_jump(d.dynamic_jump_rpm) for _, d in designs]),
    ]
    for label, vals in rows:
        flow.row([(0.0, label, {"color": C["grey"]})] + [(x, v, {"ha": "right"}) for x, v in zip(xs, vals)], size=8.2)
    flow.row(
        [(0.0, f"holds up to {sz.top_speed_rpm:.4g} rpm", {"color": C["grey"]})]
        + [(x, "yes" if h else "NO", {"ha": "right", "weight": "bold", "color": C["ok"] if h else C["fail"]}) for x, h in zip(xs, holds)],
        size=8.2,
    )
    flow.y -= flow.h(8) * 0.4
    # where it binds, and how
    where = ", ".join(f"{a:.1f}\u00b0" if a == b else f"{a:.1f}\u2013{b:.1f}\u00b0" for a, b, _ in sz.binding[:4])
    speeds = sorted({round(w) for _, _, w in sz.binding[:4]})
    line = f"Binding (kinematic): {where or _DASH}" + (f" at {', '.join(f'{w:g}' for w in speeds)} rpm" if speeds else "")
    if sz.dynamic_binding is not None:
        line += f"; dynamic: {sz.dynamic_binding[0]:.1f}\u00b0 at {sz.dynamic_binding[1]:.4g} rpm"
    lift = f"{math.degrees(sz.s_max):.4g}\u00b0 of swing" if osc else f"{sz.s_max:.4g} mm"
    line += f". Full lift s_max = {lift}: the spring's deflection beyond its preload."
    damping = nb(sz.damping.split(":")[0])  # how c was treated; the method's detail is in `camdyn size`
    notes = [(line, C["ink"], 0)]
    notes.append((f"Chosen: the least peak spring {force}; ties (a binding angle at full lift) go to the least preload. Damping: {damping}.", C["grey"], 3))
    if sz.model == "compliant":
        c, k = sz.chosen, sz.kinematic
        correction = (
            f"Dynamic correction for the compliant train, over the kinematic LP answer: preload {nb(f'{c.preload - k.preload:+.4g} ' + u['preload'])}, "
            f"peak spring {force} {nb(f'{c.peak_spring - k.peak_spring:+.4g} ' + u['spring'])}."
        )
        notes.append((correction, C["grey"], 2))
    notes += [(f"Warning: {w}.", C["warn"], 1) for w in sz.warnings]
    # what fits above the jump map, the least important notes left out first (`camdyn size` prints them all)
    size, width = 7.6, 124
    height = lambda text: flow.h(size, len(textwrap.wrap(text, width))) * 0.93 + flow.h(size) * 0.25  # noqa: E731
    room = flow.y - (_MAP_TOP + 0.03)
    for prio in sorted({p for _, _, p in notes}, reverse=True):
        if sum(height(t) for t, _, _ in notes) <= room:
            break
        notes = [n for n in notes if n[2] != prio or prio == 0]
    for text, colour, _ in notes:
        text = text.replace("N*m", _u("N*m"))
        flow.para(text, size=size, width=width, color=colour)
        flow.y -= flow.h(size) * 0.25
    _spring_jump_map(fig, data)


def _spring_jump_map(fig, data: ReportData) -> None:
    """The jump map at the case's preload: least contact force over cam speed and spring rate."""
    from ..plot import plot_jump_map

    top, bottom = _MAP_TOP, 0.095  # room for the legend under the axes
    jm = data.jump_map
    ax = fig.add_axes([_LEFT, bottom, 0.79 - _LEFT, top - bottom])
    osc = data.oscillating
    pre = f"{float(data.case.model.preload):g} {_u('N*m') if osc else 'N'}"
    title = f"jump map: least contact force at the case's preload {'T0' if osc else 'F0'} = {pre}"
    if isinstance(jm, str):
        ax.text(0.5, 0.5, "\n".join(textwrap.wrap(f"no jump map: {jm}", 90)), transform=ax.transAxes, ha="center", va="center", color=C["fail"], size=8)
        ax.set_axis_off()
        ax.set_title(title, fontsize=9)
        return
    mesh = plot_jump_map(ax, jm)
    if mesh is not None:
        mesh.set_rasterized(True)  # 1152 cells: an image in the PDF is a tenth of the bytes of as many paths
    ku = _u(jm.spring_rate_unit)
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel(f"{'torsion' if osc else 'spring'} rate ({ku})")
    from matplotlib import patheffects

    outline = [patheffects.withStroke(linewidth=2.2, foreground=C["ink"])]  # legible on light and dark colours
    ax.axvline(data.margin_rpm, color=C["margin"], lw=1.0, ls="-.", path_effects=outline, label=f"{data.case.limits.speed_margin:g} \u00d7 speed")
    ax.grid(False)
    leg = ax.legend(loc="upper center", bbox_to_anchor=(0.5 * (_LEFT + 0.79), bottom - 0.036), bbox_transform=fig.transFigure, ncol=3, fontsize=7)
    for t in leg.get_texts():
        t.set_text(_u(t.get_text()))
    if mesh is not None:
        cax = fig.add_axes([0.81, bottom, 0.015, top - bottom])
        cb = fig.colorbar(mesh, cax=cax)
        cb.set_label("least contact force (N)", fontsize=7.5)
        cb.ax.tick_params(labelsize=7)


PAGES: list[Page] = [
    Page("summary", "Summary", draw_summary),
    Page("svaj", "Follower motion (SVAJ)", draw_svaj),
    Page("cam", "Cam profile", draw_cam, lambda data: data.check.geometry is not None),
    Page("dynamics", "Dynamics", draw_dynamics),
    Page("mechanism", "Mechanism and path", draw_mechanism, lambda data: data.case.synthesis is not None),
    Page("springs", "Spring sizing", draw_springs),
]


# ===================================================================================== output
@dataclass(frozen=True)
class Written:
    """A written report: the PDF, the PNG per page, and the page titles (in order)."""

    pdf: Path
    pngs: tuple[Path, ...]
    titles: tuple[str, ...]
    verdict: str


def output_names(case_name: str, pages: list[Page]) -> tuple[str, list[str]]:
    stem = safe_stem(case_name)
    return f"{stem}.pdf", [f"{stem}-{i}-{p.slug}.png" for i, p in enumerate(pages, start=1)]


def _own_pngs(out_dir: Path, stem: str) -> list[Path]:
    pat = re.compile(rf"^{re.escape(stem)}-\d+-[a-z][a-z-]*\.png$")  # not another case's: "lecture-1-1-summary.png"
    return sorted(p for p in out_dir.glob(f"{stem}-*.png") if pat.match(p.name))


@contextmanager
def _style():
    import matplotlib

    with matplotlib.rc_context(STYLE):
        yield


def render(data: ReportData, out_dir: Path, *, progress: Progress | None = None) -> Written:
    """Draw every page that applies to the case into ``out_dir``: the PDF and one PNG per page."""
    import matplotlib
    from matplotlib.backends.backend_pdf import PdfPages
    from matplotlib.figure import Figure

    out_dir = output_dir(out_dir, "report")
    pages = [p for p in PAGES if p.applies(data)]
    pdf_name, png_names = output_names(data.case.name, pages)
    stem = pdf_name[:-4]
    version = _version()
    meta = {
        "Title": f"camdyn design review: {data.case.name}",
        "Subject": " | ".join(p.title for p in pages),
        "Creator": "camdyn",
        "Producer": f"camdyn {version} (matplotlib {matplotlib.__version__})",
        "CreationDate": None,
        "ModDate": None,
    }
    pngs = []
    tick = counter(progress, f"{data.case.name}: report pages", len(pages))
    with _style(), PdfPages(out_dir / pdf_name, metadata=meta) as pdf:
        for i, page in enumerate(pages, start=1):
            fig = Figure(figsize=A4)
            _header(fig, data, page.title, i, len(pages))
            page.draw(fig, data)
            pdf.savefig(fig)
            png = out_dir / png_names[i - 1]
            _save_png(fig, png, version)
            pngs.append(png)
            tick()
    for old in _own_pngs(out_dir, stem):
        if old.name not in png_names:
            old.unlink()
    return Written(out_dir / pdf_name, tuple(pngs), tuple(p.title for p in pages), data.check.verdict)


def _save_png(fig, path: Path, version: str) -> None:
    """The page as a 256-colour PNG (plots and text survive a palette untouched; a third of the bytes)."""
    import io

    from PIL import Image, PngImagePlugin

    buf = io.BytesIO()
    fig.savefig(buf, dpi=DPI, format="png")
    buf.seek(0)
    with Image.open(buf) as im:
        pal = im.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    info = PngImagePlugin.PngInfo()
    info.add_text("Software", f"camdyn {version}")
    pal.save(path, format="PNG", optimize=True, pnginfo=info)


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("camdyn")
    except PackageNotFoundError:  # pragma: no cover
        return "0"


def write_report(case, out_dir, *, check=None, speed_rpm: float | None = None, progress: Progress | None = None) -> Written:
    """Check ``case`` (unless ``check``, a :class:`camdyn.design.checks.CheckReport`, is given) and write its report."""
    from ..design.checks import run_check

    if check is None:
        check = run_check(case, speed_rpm)
    return render(ReportData(case, check), Path(out_dir), progress=progress)


def report_cases(paths: list[str | Path], out_dir, *, speed_rpm: float | None = None, specs=None, progress: Progress | None = None) -> list[Written]:
    """Load, check and report every case file in ``paths`` (bad input stops before any work, naming the file).
    ``specs``: the files' validated :class:`camdyn.schema.CaseSpec`, where the caller has read them already."""
    from ..model.case import build_case, load_case

    output_dir(out_dir, "report")
    cases = []
    for i, p in enumerate(paths):
        try:
            cases.append(load_case(p) if specs is None else build_case(specs[i], source=Path(p)))
        except CamdynError as err:
            raise type(err)(f"{p}: {err.where}" if err.where else str(p), err.message) from None
    stems: dict[str, str] = {}
    for p, c in zip(paths, cases):
        stem = safe_stem(c.name)
        if stem in stems:
            raise InputError(str(p), f"case name {c.name!r} is also the name of {stems[stem]}: their reports would overwrite each other")
        stems[stem] = str(p)
    out = []
    tick = counter(progress, "cases", len(cases))
    for p, case in zip(paths, cases):
        try:
            out.append(write_report(case, out_dir, speed_rpm=speed_rpm, progress=progress))
        except CamdynError as err:
            raise type(err)(f"{p}: {err.where}" if err.where else str(p), err.message) from None
        tick()
    return out
