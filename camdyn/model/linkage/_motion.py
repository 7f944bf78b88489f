"""The follower motion of a cam-linkage: s(theta) or phi(theta) with exact derivatives, by inverting the crank
angle Theta(u) of the path parameter u."""

from __future__ import annotations

from typing import TYPE_CHECKING

import equinox as eqx
import jax
import jax.numpy as jnp
from jax.typing import ArrayLike

from ..._core.jit import cached_jit
from ..._core.units import TWO_PI
from ..motion import Motion
from ..paths import taylor
from ._chains import CCMChain, OscillatingChain
from ._crank import CrankDyad

if TYPE_CHECKING:
    from ._chains import LinkChain


def _wrap(x):
    return jnp.mod(x + jnp.pi, TWO_PI) - jnp.pi


class CamLinkMotion(Motion):
    """Follower motion of a cam-linkage synthesis: s(theta) (mm) or phi(theta) (rad), exact derivatives.

    theta is the cam angle turned from the path start in the cam's sense of rotation. Evaluation: find u with
    Theta(u) = theta by safeguarded Newton from the table bracket, then with Theta^(k)(u), s^(k)(u) (nested
    forward autodiff) s' = s_u / Theta_u, s'' = (s_uu Theta_u - s_u Theta_uu) / Theta_u^3 and
    s''' = (s_uuu Theta_u^2 - 3 s_uu Theta_u Theta_uu + s_u (3 Theta_uu^2 - Theta_u Theta_uuu)) / Theta_u^5.
    """

    chain: CCMChain | OscillatingChain
    crank_dyad: CrankDyad
    theta0: jax.Array  # crank angle at u = 0, rad
    out0: jax.Array  # follower coordinate at zero lift
    tab_u: jax.Array  # (N + 1,) table of u and cam angle, Theta increasing from 0 to 2 pi
    tab_theta: jax.Array
    sense: jax.Array  # +1: crank turns anticlockwise, -1 clockwise
    unit: str = eqx.field(static=True)
    breaks_deg: tuple[float, ...] = eqx.field(static=True)

    def crank_angle(self, u: ArrayLike) -> jax.Array:
        """Crank angle at u (rad, not unwrapped)."""
        alpha, phi = self.crank_dyad.angles(self.chain.p_side, u)
        return alpha + phi

    def cam_angle(self, u: ArrayLike) -> jax.Array:
        """Cam angle Theta(u) at scalar u (rad, not unwrapped): the crank angle from its start, in the sense
        the cam turns."""
        return self.sense * (self.crank_angle(u) - self.theta0)

    def _pair(self, u):
        th = self.crank_angle(u)
        return jnp.stack([self.sense * (th - self.theta0), self.chain.output(u, th) - self.out0])

    def u_of(self, theta: ArrayLike) -> jax.Array:
        """Path parameter u (scalar) at cam angle theta (rad): Newton with a bisection safeguard in the table cell.

        Theta(u) is increasing; the bracket [a, b] shrinks with every residual sign, and a Newton step that
        leaves it is replaced by bisection (robust where Theta' is unbounded, at a sharp corner).
        """
        theta = jnp.mod(theta, TWO_PI)
        i = jnp.clip(jnp.searchsorted(self.tab_theta, theta, side="right") - 1, 0, self.tab_u.shape[0] - 2)
        a, b = self.tab_u[i], self.tab_u[i + 1]
        ta, tb = self.tab_theta[i], self.tab_theta[i + 1]
        u = a + (b - a) * (theta - ta) / (tb - ta)

        def step(
            state: tuple[jax.Array, jax.Array, jax.Array], _: None
        ) -> tuple[tuple[jax.Array, jax.Array, jax.Array], None]:
            u, a, b = state
            val, der = jax.jvp(self.cam_angle, (u,), (jnp.ones_like(u),))
            res = _wrap(val - theta)
            a, b = jnp.where(res < 0.0, u, a), jnp.where(res > 0.0, u, b)
            nxt = u - res / jnp.where(der > 0.0, der, 1.0)
            # closed bracket: a converged iterate sits on the end its own residual set, and a Newton step of
            # zero length must not be mistaken for one that left the bracket (it would bisect away from the root)
            ok = (nxt >= a) & (nxt <= b) & (der > 0.0)
            return (jnp.where(res == 0.0, u, jnp.where(ok, nxt, 0.5 * (a + b))), a, b), None

        (u, _, _), _ = jax.lax.scan(step, (u, a, b), None, length=8)
        return jax.lax.stop_gradient(u)

    def at_u(self, u: ArrayLike) -> jax.Array:
        """(Theta, s) and their first three u-derivatives at scalar u: (4, 2)."""
        return jnp.stack(taylor(self._pair, u, 3))

    def _one(self, theta):
        tv = self.at_u(self.u_of(theta))
        t1, t2, t3 = tv[1, 0], tv[2, 0], tv[3, 0]
        s0, s1, s2, s3 = tv[0, 1], tv[1, 1], tv[2, 1], tv[3, 1]
        d1 = s1 / t1
        d2 = (s2 * t1 - s1 * t2) / t1**3
        d3 = (s3 * t1**2 - 3.0 * s2 * t1 * t2 + s1 * (3.0 * t2**2 - t1 * t3)) / t1**5
        return jnp.stack([s0, d1, d2, d3])

    def jit_form(self) -> CamLinkMotion:
        """Without its breaks (which only the step-size controller reads): one compiled program serves every
        path of a kind."""
        return with_breaks(self, ())

    def __call__(self, theta: ArrayLike) -> jax.Array:
        theta = jnp.asarray(theta, dtype=float)
        out = jax.vmap(self._one)(theta.ravel())  # (n, 4)
        return out.T.reshape(4, *theta.shape)


@cached_jit
def tabulate(motion: CamLinkMotion, u: ArrayLike) -> jax.Array:
    """Theta_raw, follower coordinate and their u-derivative on a grid."""

    def one(v: ArrayLike) -> jax.Array:
        val, der = jax.jvp(motion._pair, (v,), (jnp.ones_like(v),))
        return jnp.concatenate([val, der])

    return jax.vmap(one)(u)


def with_breaks(m: CamLinkMotion, breaks: tuple[float, ...]) -> CamLinkMotion:
    """The same motion with other ``breaks_deg`` (internal jitted helpers use ``()`` so they compile once)."""
    return CamLinkMotion(
        chain=m.chain,
        crank_dyad=m.crank_dyad,
        theta0=m.theta0,
        out0=m.out0,
        tab_u=m.tab_u,
        tab_theta=m.tab_theta,
        sense=m.sense,
        unit=m.unit,
        breaks_deg=breaks,
    )


@cached_jit
def sample(motion: CamLinkMotion, theta: ArrayLike) -> tuple[jax.Array, jax.Array]:
    """Path parameters u (n,) and follower value and first derivative per radian of cam angle (n, 2) at theta.

    First order only (one jvp): the synthesis does not need the third-order Taylor program that the full
    ``motion(theta)`` compiles, so it stays fast; s'' for sizing the cam comes from differences of s'.
    """

    def one(th: ArrayLike) -> tuple[jax.Array, jax.Array]:
        u = motion.u_of(th)
        val, der = jax.jvp(motion._pair, (u,), (jnp.ones_like(u),))
        return u, jnp.stack([val[1], der[1] / der[0]])

    return jax.vmap(one)(theta)


@cached_jit
def joint_points(chain: LinkChain, u: ArrayLike, theta: ArrayLike) -> dict[str, jax.Array]:
    return jax.vmap(chain.points)(u, theta)
