"""The two cam-linkages a path can drive, as chains solved backwards from the path point: the CCM of a profile
cutter and Ye & Smith's oscillating mechanism. Each gives the path-side point of its crank dyad and its
follower coordinate; coordinates are relative to the cam centre, mm.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import NumericalError
from ..._core.jit import device_array
from ...schema import MechanismSpec
from ..paths import Path
from ._batch import vmap_scalar, where_point
from ._dyads import cross2, rrp, rrr, rrr_reach_miss, turn, unit


class CCMChain(eqx.Module):
    """CCM (seed 003): crank A-B on the camshaft, coupler B-T carrying joint C, link C-E, slider E on a line.

    Coordinates relative to the cam centre A. Output: slider coordinate p of E along ``direction`` (mm).
    """

    path: Path
    center: jax.Array  # A in the case frame
    crank: jax.Array
    coupler: jax.Array
    joint: jax.Array  # C in the coupler frame (x along B->T, y to its left), mm
    link: jax.Array
    origin: jax.Array  # a point of the slider line (relative to A)
    direction: jax.Array  # unit lift direction
    slider_mode: float = eqx.field(static=True)

    def p_side(self, u: ArrayLike) -> jax.Array:
        return self.path.point(u) - self.center

    def points(self, u: ArrayLike, theta: ArrayLike) -> dict[str, jax.Array]:
        """Joint positions relative to A at path parameter u and crank angle theta (rad)."""
        t = self.p_side(u)
        b = self.crank * unit(theta)
        ex = (t - b) / self.coupler
        c = b + self.joint[0] * ex + self.joint[1] * jnp.stack([-ex[1], ex[0]])
        p = rrp(c, self.origin, self.direction, self.link, self.slider_mode)
        return {"B": b, "T": t, "C": c, "E": self.origin + p * self.direction, "p": p}

    def output(self, u: ArrayLike, theta: ArrayLike) -> jax.Array:
        return self.points(u, theta)["p"]


class OscillatingChain(eqx.Module):
    """Ye & Smith (seed 000): path point F, link F-C through the pin B, follower D-C with roller arm D-E.

    Coordinates relative to the cam centre O. Output: psi, the arm angle turned clockwise from D->O to D->E.
    """

    path: Path
    center: jax.Array  # O in the case frame
    pivot: jax.Array  # D relative to O
    path_link: jax.Array  # FC
    follower_link: jax.Array  # DC
    pin: jax.Array  # FB along F->C
    arm: jax.Array  # DE
    arm_angle: jax.Array  # angle D->C to D->E, rad anticlockwise
    follower_mode: float = eqx.field(static=True)

    def _fc(self, u):
        f = self.path.point(u) - self.center
        return f, rrr(f, self.pivot, self.path_link, self.follower_link, self.follower_mode)

    def p_side(self, u: ArrayLike) -> jax.Array:
        f, c = self._fc(u)
        return f + self.pin * (c - f) / self.path_link

    def points(self, u: ArrayLike, theta: ArrayLike | None = None) -> dict[str, jax.Array]:
        f, c = self._fc(u)
        b = f + self.pin * (c - f) / self.path_link
        e = self.pivot + self.arm * turn((c - self.pivot) / self.follower_link, self.arm_angle)
        a, dn = e - self.pivot, -self.pivot
        psi = jnp.arctan2(cross2(a, dn), jnp.sum(a * dn))
        return {"F": f, "C": c, "B": b, "E": e, "psi": psi}

    def output(self, u: ArrayLike, theta: ArrayLike) -> jax.Array:
        return self.points(u)["psi"]


LinkChain = CCMChain | OscillatingChain  # the chain a cam-linkage mechanism solves


def make_chain(path: Path, ms: MechanismSpec, r: float, coupler: float) -> CCMChain | OscillatingChain:
    """The chain of a ``[mechanism]`` table tracing ``path``, with crank ``r`` and ``coupler`` (mm)."""
    c0 = np.asarray(ms.cam_center, dtype=float)
    a = device_array
    if ms.type == "ccm":
        jd = ms.joint_distance if ms.joint_distance is not None else coupler
        ja = math.radians(ms.joint_angle)
        sp = np.asarray(ms.slider_point if ms.slider_point is not None else ms.cam_center, dtype=float) - np.asarray(
            ms.cam_center
        )
        assert ms.slider_angle is not None  # the schema: a ccm needs it
        slider = math.radians(ms.slider_angle)
        return CCMChain(
            path=path,
            center=a(c0),
            crank=a(r),
            coupler=a(coupler),
            joint=a([jd * math.cos(ja), jd * math.sin(ja)]),
            link=a(ms.link),
            origin=a(sp),
            direction=a([math.cos(slider), math.sin(slider)]),
            slider_mode=float(ms.slider_mode),
        )
    assert ms.pin_distance is not None  # the schema: an oscillating mechanism needs it
    return OscillatingChain(
        path=path,
        center=a(c0),
        pivot=a(np.asarray(ms.pivot, dtype=float) - c0),
        path_link=a(ms.path_link),
        follower_link=a(ms.follower_link),
        pin=a(float(ms.pin_distance)),
        arm=a(ms.arm),
        arm_angle=a(math.radians(ms.arm_angle)),
        follower_mode=float(ms.follower_mode),
    )


def check_follower_side(chain: LinkChain, ms: MechanismSpec, u_grid: np.ndarray) -> None:
    """The path-driven follower dyad must close at every path point (else: where and by how much)."""
    if ms.type != "oscillating":
        return
    assert isinstance(chain, OscillatingChain)  # an oscillating mechanism's chain
    assert ms.path_link is not None and ms.follower_link is not None  # the schema: an oscillating mechanism needs them
    f = vmap_scalar(chain.path.point, u_grid) - np.asarray(chain.center)
    miss = np.asarray(rrr_reach_miss(f, np.asarray(chain.pivot), ms.path_link, ms.follower_link))
    i = int(np.argmax(miss))
    if miss[i] > 0.0:
        raise NumericalError(
            where_point(i),
            f"dyad F-C-D cannot close: reach missed by {miss[i]:.4g} mm (|DF| = "
            f"{np.linalg.norm(f[i] - np.asarray(chain.pivot)):.4g} mm, FC + DC = {ms.path_link + ms.follower_link:g} "
            f"mm, |FC - DC| = {abs(ms.path_link - ms.follower_link):g} mm)",
        )


def check_ccm_slider(chain: CCMChain, motion_pts: dict, ms: MechanismSpec) -> None:
    """The link C-E must reach the slider line at every path point (else: where and by how much)."""
    c = np.asarray(motion_pts["C"])
    off = np.abs(cross2(np.asarray(chain.direction), c - np.asarray(chain.origin)))
    miss = off - ms.link
    i = int(np.argmax(miss))
    if miss[i] > 0.0:
        raise NumericalError(
            where_point(i),
            f"dyad C-E-slider cannot close: the link C-E ({ms.link:g} mm) misses the slider line by {miss[i]:.4g} mm",
        )
