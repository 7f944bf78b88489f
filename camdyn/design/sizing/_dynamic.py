"""The dynamic correction of a compliant follower: its steady state in contact is exact in the frequency domain
(:func:`camdyn.model.dynamics.linear_contact_force`) and affine in the preload,
``Fc(theta, w; k, F0) = alpha F0 + G(theta, w; k)``, alpha = k_f / (k + k_f); so the least preload for a rate is
exact, and the dynamic peak force ``k s_max + F0_dyn(k)`` is minimized over sqrt(k)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..._core.errors import NumericalError
from ..._core.units import FFT_GRID, RPM, TWO_PI
from ...model import dynamics as dyn
from ._problem import Grid, Problem
from ._sqrt_k import minimize_in_sqrt_k

_N_FFT = FFT_GRID  # frequency-domain steady state
_N_SPEEDS = 160  # dynamic requirement: 0 and 160 speeds up to W
_N_REFINE = 17
_N_VERIFY_CHUNKS = 7  # verification: 7 * 161 speeds in [0, W]
_N_SCAN = 24
TIE_DYN = 1e-6
_FIX_ROUNDS = 3


@dataclass(frozen=True)
class Dynamic:
    """The dynamic requirement of a compliant follower on the FFT angle grid and the speeds of [0, W]."""

    p: Problem
    arm: np.ndarray  # (N_FFT,) m: lever arm per angle (1 translating)
    req: np.ndarray  # (N_FFT,) F_min * arm
    speeds: np.ndarray  # (N_SPEEDS + 1,) rad/s
    _verified: dict = field(default_factory=dict, compare=False, repr=False)  # memo of verify (pure in (k, F0))

    @classmethod
    def of(cls, p: Problem) -> Dynamic:
        arm = p.arm(np.arange(_N_FFT) * (TWO_PI / _N_FFT))
        return cls(p, arm, p.fmin * arm, np.linspace(0.0, p.W, _N_SPEEDS + 1))

    def alpha(self, k: float) -> float:
        """dFc / dF0 = k_f / (k + k_f)."""
        return dyn.preload_share(k, self.p.kf)

    def contact_force(self, k: float, f0: float, speeds: np.ndarray) -> np.ndarray:
        """Frequency-domain steady-state interface force (N or N*m), shape (len(speeds), N_FFT)."""
        p = self.p
        out = np.asarray(
            dyn.linear_contact_force(p.motion, p.with_spring(k, f0), np.asarray(speeds, dtype=float), _N_FFT)
        )
        if not np.all(np.isfinite(out)):
            raise NumericalError(
                f"sizing, rate {p.kind.rate_from_si(k):.4g}", "the steady-state contact force is not finite"
            )
        return out

    def _worst(self, k, speeds):
        """The largest deficit ``F_min arm - Fc(F0 = 0)`` over angles and ``speeds``: (deficit, speed, angle index)."""
        d = self.req[None, :] - self.contact_force(k, 0.0, speeds)
        j = np.argmax(d, axis=1)
        dm = d[np.arange(len(speeds)), j]
        i = int(np.argmax(dm))
        return float(dm[i]), float(speeds[i]), int(j[i])

    def preload(self, k: float, refine: bool = True) -> tuple[float, float, float]:
        """The least preload for rate k: (F0, theta_deg, speed_rpm) of the binding point; ``refine``: the worst
        speed refined twice on 17 speeds around it."""
        best, w, j = self._worst(k, self.speeds)
        if refine:
            h = self.speeds[1] - self.speeds[0]
            for _ in range(2):
                ws = np.linspace(max(w - h, 0.0), min(w + h, self.p.W), _N_REFINE)
                b2, w2, j2 = self._worst(k, ws)
                if b2 > best:
                    best, w, j = b2, w2, j2
                h = ws[1] - ws[0]
        return max(best / self.alpha(k), self.p.f0_lo), 360.0 * j / _N_FFT, w / RPM

    def verify(self, k: float, f0: float) -> tuple:
        """Least and largest dynamic interface force (N) on 1127 speeds in [0, W], each (value, theta_deg,
        speed_rpm), and the least slack of the requirement (N or N*m)."""
        key = (float(k), float(f0))
        if key not in self._verified:
            self._verified[key] = self._verify(k, f0)
        return self._verified[key]

    def _verify(self, k, f0):
        speeds = np.linspace(0.0, self.p.W, _N_VERIFY_CHUNKS * (_N_SPEEDS + 1))
        lo = (math.inf, 0, 0.0)
        hi = (-math.inf, 0, 0.0)
        slack_min = math.inf
        for chunk in speeds.reshape(_N_VERIFY_CHUNKS, -1):
            fc = self.contact_force(k, f0, chunk)
            slack_min = min(slack_min, float(np.min(fc - self.req[None, :])))
            fn = fc / self.arm[None, :]
            i, j = np.unravel_index(int(np.argmin(fn)), fn.shape)
            if fn[i, j] < lo[0]:
                lo = (float(fn[i, j]), 360.0 * j / _N_FFT, float(chunk[i]) / RPM)
            i, j = np.unravel_index(int(np.argmax(fn)), fn.shape)
            if fn[i, j] > hi[0]:
                hi = (float(fn[i, j]), 360.0 * j / _N_FFT, float(chunk[i]) / RPM)
        return lo, hi, slack_min

    def raised(self, k: float, f0: float, rtol: float = 0.0) -> float:
        """F0 raised by the verification's deficit / alpha where the deficit exceeds ``rtol`` of the preload (the
        force is affine in F0, so the fix is exact)."""
        _, _, slack = self.verify(k, f0)
        if slack >= -rtol * max(1.0, abs(f0)):
            return f0
        return f0 - slack * (k + self.p.kf) / self.p.kf


def dynamic_answer(d: Dynamic, grid: Grid, k_kin: float) -> tuple[float, float, tuple[float, float]]:
    """(k, F0, (theta_deg, speed_rpm) of the binding point) of the dynamic peak force ``k s_max + F0_dyn(k)``:
    scanned in sqrt k from min_rate to the rate beyond which even the static requirement at least lift costs more
    than the kinematic answer does dynamically, then bounded Brent around the best (ties within 1e-6 to the
    largest k); the answer verified on 1127 speeds and F0 raised by any remaining deficit."""
    p = d.p
    peak_dyn = lambda u: u * u * p.s_max + d.preload(u * u)[0]  # noqa: E731
    p_ref = peak_dyn(math.sqrt(k_kin))
    k_hi = max(p.k_lo, (p_ref - grid.req[grid.i_min]) / (p.s_max - grid.s[grid.i_min]), 2.0 * k_kin, 1e-12)
    u = minimize_in_sqrt_k(
        peak_dyn, math.sqrt(p.k_lo), math.sqrt(k_hi), TIE_DYN, scan=_N_SCAN, seeds=(math.sqrt(k_kin),)
    )
    k = u * u
    f0, th, w = d.preload(k)
    for _ in range(_FIX_ROUNDS):
        raised = d.raised(k, f0, rtol=1e-9)
        if raised == f0:
            break
        f0 = raised
    return k, f0, (th, w)
