"""The valvetrain fast path's exact linear machinery: a linear system's propagators over a fixed angle grid (the
matrix exponential of the system augmented with its input's cubic Taylor chain), the chained steps as a modal
recurrence, and the first angle where a guard (a contact's condition) falls below zero, located on that exact
solution (:mod:`._valveevent` builds the valve's systems, :mod:`._valvefast` reads them)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

_SPLIT = 64  # a contact change inside a step: the step cut in 64, twice over
_FRESH = 2.0 ** np.arange(-23, 1)  # a guard that starts at zero: the span's first cuts doubling from 1.2e-7 of it
_MARCH = 64  # a stretch's first chunk of fine steps (then four times what it has, to the revolution's end)
ORDER = 4  # the input's Taylor chain: value, slope, curvature, third derivative (a cubic)

Index = int | float | np.ndarray  # fine steps, or angles into them (rad): one, or one per state
Guard = Callable[[np.ndarray, Index, Index], np.ndarray]  # states, their steps and angles -> > 0 while a mode holds


def batched_expm(z: np.ndarray) -> np.ndarray:
    """``exp`` of a stack of small matrices (..., m, m), batched: scaled to a norm below 1/4, a Taylor series to
    the 12th power (a remainder below 3e-18), squared back. scipy's ``expm`` goes matrix by matrix (its Pade
    step costs milliseconds for each of the thousands a speed asks for)."""
    norm = np.max(np.sum(np.abs(z), axis=-1), axis=-1)
    squarings = np.maximum(0, np.ceil(np.log2(np.maximum(norm, 1e-300)) + 2)).astype(int)
    top = int(squarings.max()) if squarings.size else 0
    a = z / (2.0**squarings)[..., None, None]
    # the series to a^12 by Paterson-Stockmeyer: a^2, a^3, a^4, then Horner in a^4 over blocks of four terms
    # (5 products, not 12: each is a numpy call on a stack of small matrices)
    eye = np.broadcast_to(np.eye(z.shape[-1]), z.shape)
    a2 = a @ a
    a3 = a2 @ a
    a4 = a3 @ a
    c = [1.0 / math.factorial(k) for k in range(13)]
    out = c[12] * a4 + (c[8] * eye + c[9] * a + c[10] * a2 + c[11] * a3)
    for k in (4, 0):
        out = out @ a4 + (c[k] * eye + c[k + 1] * a + c[k + 2] * a2 + c[k + 3] * a3)
    for i in range(top):
        more = squarings > i
        if more.all():
            out = out @ out
        else:
            out[more] = out[more] @ out[more]
    return out


def _shift(taylor: np.ndarray, tau: float) -> np.ndarray:
    """A cubic's Taylor coefficients moved ``tau`` along its step."""
    a0, a1, a2, a3 = taylor
    return np.array(
        [a0 + a1 * tau + a2 * tau**2 / 2 + a3 * tau**3 / 6, a1 + a2 * tau + a3 * tau**2 / 2, a2 + a3 * tau, a3]
    )


def recur(lam: np.ndarray, g: np.ndarray, z0: np.ndarray) -> np.ndarray:
    """``z[:, k + 1] = lam z[:, k] + g[:, k]`` from ``z[:, 0] = z0`` for every mode at once (``lam`` and ``z0``:
    (modes,), ``g``: (modes, steps)): (modes, steps + 1). In blocks short enough that every decaying mode's powers
    within one stay within 1e3 of each other, each block a cumulative sum:
    ``z[k + i] = lam^i (z[k] + sum_{j < i} g[k + j] lam^-(j + 1))``. A mode gone within a step (``|lam|`` below
    1e-12) is its forcing."""
    lam, g, z0 = np.asarray(lam, complex), np.asarray(g, complex), np.asarray(z0, complex)
    count = g.shape[1]
    out = np.empty((lam.size, count + 1), complex)
    out[:, 0] = z0
    size = np.abs(lam)
    gone = size < 1e-12
    live = np.where(gone, 1.0, lam)  # its powers stay finite; its rows are set apart below
    least = float(np.min(size[~gone], initial=1.0))
    block = count if least >= 1.0 else max(1, min(count, int(math.log(1e3) / -math.log(least))))
    # lam ** k and lam ** -k, once for the blocks of one length: numpy's complex ** is 7x slower, no closer
    exponent = np.arange(1, block + 1)[None, :] * np.log(live)[:, None]
    full, inverse = np.exp(exponent), np.exp(-exponent)
    k = 0
    while k < count:
        m = min(block, count - k)
        out[:, k + 1 : k + m + 1] = full[:, :m] * (
            out[:, k : k + 1] + np.cumsum(g[:, k : k + m] * inverse[:, :m], axis=1)
        )
        k += m
    out[gone, 1:] = g[gone]
    return out


class Linear:
    """The valve's linear system ``y' = A y + e (w0 + b)`` (y: the valve's (x, x'), or with the spring's surge chain
    its lumps' and the valve's lifts, then their speeds; e drives the last, w0 the cubic input) and its exact
    propagators: ``expm`` of the system augmented with the input's Taylor chain and the constant. ``b`` an array: a
    constant in each state's derivative (``y' = A y + b + e w0``)."""

    def __init__(self, a: np.ndarray, b: float | np.ndarray, taylor: np.ndarray, h: float) -> None:
        n = a.shape[0]
        z = np.zeros((n + ORDER + 1, n + ORDER + 1))
        z[:n, :n] = a
        z[n - 1, n] = 1.0  # the input drives the last state's derivative
        if np.ndim(b):  # a constant in every derivative (two masses flying together)
            z[:n, n + ORDER] = b
        else:
            z[n - 1, n + ORDER] = b
        for i in range(ORDER - 1):
            z[n + i, n + i + 1] = 1.0
        self.z, self.n, self.taylor, self.h = z, n, taylor, h
        self._step: tuple | None = None  # the full step's propagator and its modes, once
        self._steps: dict[bytes, np.ndarray] = {}  # propagators by their angles
        self._powers: dict[float, np.ndarray] = {}  # :meth:`even`'s propagators (transposed) by their angle

    def steps(self, deltas: np.ndarray) -> np.ndarray:
        """The augmented propagators over angles ``deltas`` (rad): (len, n, n + 5)."""
        deltas = np.asarray(deltas, dtype=float)
        key = deltas.tobytes()
        if key not in self._steps:  # a step's cuts from its start recur: kept
            if len(self._steps) > 64:
                self._steps.clear()
            self._steps[key] = batched_expm(self.z[None] * deltas[:, None, None])[:, : self.n, :]
        return self._steps[key]

    def _source(self, step: int, tau: float, y: np.ndarray) -> np.ndarray:
        """The augmented state ``tau`` rad into fine step ``step``: ``y``, the input's Taylor chain there, 1."""
        return np.concatenate([y, _shift(self.taylor[step], tau), [1.0]])

    def advance(self, step: int, tau: float, y: np.ndarray, deltas: np.ndarray) -> np.ndarray:
        """The states at ``deltas`` past angle ``tau`` into fine step ``step`` from ``y`` there: (len, n)."""
        return self.steps(deltas) @ self._source(step, tau, y)

    def even(self, step: int, tau: float, y: np.ndarray, delta: float, count: int) -> np.ndarray:
        """The states at ``0, delta, ..., count delta`` past angle ``tau`` into fine step ``step`` from ``y`` there:
        (count + 1, n). One propagator and its powers by squaring (the augmented system is time-invariant: the
        state ``i delta`` on is ``E(delta)^i`` of the augmented start), not an exponential per angle, which for the
        surge chain's systems (37 x 37 augmented) cost a millisecond a cut."""
        aug = self._source(step, tau, y)[None]
        power = self._powers.get(delta)
        if power is None:  # a step's cuts from its start recur: kept
            if len(self._powers) > 64:
                self._powers.clear()
            power = self._powers[delta] = batched_expm((self.z * delta)[None])[0].T
        while len(aug) < count + 1:
            more = aug[: count + 1 - len(aug)] @ power
            aug = np.concatenate([aug, more])
            if len(aug) < count + 1:
                power = power @ power
        return aug[:, : self.n]

    def doubling(self, step: int, tau: float, y: np.ndarray, delta: float, count: int) -> np.ndarray:
        """The states at ``delta, 2 delta, 4 delta, ...`` (``count`` of them) past angle ``tau`` into fine step
        ``step`` from ``y`` there: (count, n). One propagator squared in turn."""
        src = self._source(step, tau, y)
        power = batched_expm((self.z * delta)[None])[0]
        out = np.empty((count, self.n))
        for i in range(count):
            out[i] = power[: self.n] @ src
            if i + 1 < count:
                power = power @ power
        return out

    def march(self, step: int, y: np.ndarray, count: int | None = None) -> np.ndarray:
        """The states at the nodes from ``step`` (where the state is ``y``) to the last, or the next ``count`` steps
        of them: (steps + 1, n)."""
        if self._step is None:
            e = self.steps(np.array([self.h]))[0]
            phi = e[:, : self.n]
            lam, vec = np.linalg.eig(phi)
            inv = None if np.linalg.cond(vec) > 1e8 else np.linalg.inv(vec)
            # a real system's complex modes come in conjugate pairs (LAPACK gives them so, the one with the positive
            # imaginary part first): one of each pair, twice its real part
            im = np.imag(lam)
            paired = np.array_equal(lam[im < 0.0], np.conj(lam[im > 0.0])) and np.array_equal(
                vec[:, im < 0.0], np.conj(vec[:, im > 0.0])
            )
            half = im >= 0.0 if paired else np.ones(lam.size, bool)
            twice = np.where(im > 0.0, 2.0, 1.0)[half] if paired else 1.0
            modes = (lam[half], vec[:, half] * twice, None if inv is None else inv[half])
            self._step = (phi, e[:, self.n :], modes)
        phi, gam, (lam, vec, inv) = self._step
        taylor = self.taylor[step:] if count is None else self.taylor[step : step + count]
        if not taylor.shape[0]:
            return y[None]
        forcing = np.concatenate([taylor, np.ones((taylor.shape[0], 1))], axis=1) @ gam.T  # (steps, n)
        if inv is None:  # (nearly) repeated modes: step by step
            out = [y]
            for g in forcing:
                out.append(phi @ out[-1] + g)
            return np.array(out)
        z = recur(lam, _product(inv, forcing.T), inv @ y)
        return np.real(_product(vec, z)).T


def _product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a @ b`` for a few modes' long rows: by einsum where ``a`` has a few columns (a BLAS product that long runs
    on threads that then spin, twice the CPU for the same wall on a 2-core machine), by BLAS where it has many (the
    surge chain's 16 modes)."""
    return a @ b if a.shape[1] > 4 else np.einsum("ij,jk->ik", a, b)


class Unsure(Exception):
    """The fast path cannot say: the caller runs the diffrax model."""


def cross(
    lin: Linear, step: int, tau: float, y: np.ndarray, span: float, guard: Guard, fresh: bool
) -> tuple[float, np.ndarray] | None:
    """The first angle past ``tau`` in fine step ``step`` (from state ``y``), within ``span`` (rad), where
    ``guard(states, steps, taus)`` falls below zero: (delta, state) or None. The span cut in :data:`_SPLIT` finds
    the first sign change (``fresh``: the guard starts at zero, a rebound off the seat: the cuts doubling from 1.2e-7
    of the span, :data:`_FRESH`), that cut in :data:`_SPLIT` again, the guard interpolated linearly across the last
    (a width of 1/4096 of a fine step: an error of its square), and the state there from the exact propagator."""
    lo, width, g_lo, g_hi, y_lo = 0.0, span, 0.0, 0.0, y
    for r in range(2):
        if r == 0 and fresh:
            ds = span * _FRESH
            ys = lin.doubling(step, tau, y, float(ds[0]), _FRESH.size)
        else:
            ds = lo + np.linspace(0.0, width, _SPLIT + 1)
            ys = lin.even(step, tau + lo, y_lo, width / _SPLIT, _SPLIT)
        g = guard(ys, step, tau + ds)
        below = np.nonzero(g < 0.0)[0]
        if r == 0 and not fresh:
            below = below[below > 0]
        if not below.size:
            return None
        j = int(below[0])
        if j == 0:  # fresh: below at the first cut already
            lo, g_lo, width, y_lo = 0.0, 0.0, ds[0], y
        else:
            lo, g_lo, width = ds[j - 1], float(g[j - 1]), ds[j] - ds[j - 1]
            # a doubling's states carry the rounding of its squarings (up to 2^24 eps): the next round starts from
            # the exact propagator's
            y_lo = lin.advance(step, tau, y, np.array([lo]))[0] if r == 0 and fresh else ys[j - 1]
        g_hi = float(g[j])
    f = min(max(g_lo / (g_lo - g_hi), 0.0), 1.0) if g_lo != g_hi else 1.0
    root = lo + f * width
    return root, lin.advance(step, tau, y, np.array([root]))[0]


def stretch_to(
    lin: Linear, step: int, tau: float, y: np.ndarray, guard: Guard, fresh: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple | None]:
    """From angle ``tau`` into fine step ``step`` with state ``y`` on ``lin`` to where ``guard`` first falls below
    zero: the states passed (at their fine steps and angles into them) and the event (step, tau, state), None where
    the revolution ends first."""
    h = lin.h
    got = cross(lin, step, tau, y, h - tau, guard, fresh)
    if got is not None:
        ds = np.linspace(0.0, got[0], 9)[1:]
        along = lin.even(step, tau, y, got[0] / 8, 8)[1:]
        return along, np.full(ds.size, step), tau + ds, (step, tau + got[0], got[1])
    nodes = lin.march(step + 1, lin.advance(step, tau, y, np.array([h - tau]))[0], _MARCH)
    last = len(lin.taylor)  # the last node: the revolution's end
    while True:  # a chunk at a time: most stretches end within a few steps
        idx = step + 1 + np.arange(len(nodes))
        below = np.nonzero(guard(nodes, idx, np.zeros(len(nodes))) < 0.0)[0]
        if below.size or idx[-1] >= last:
            break
        nodes = np.concatenate([nodes, lin.march(int(idx[-1]), nodes[-1], 4 * len(nodes))[1:]])
    if not below.size:
        return nodes, idx, np.zeros(len(nodes)), None
    q = int(below[0])
    got = cross(lin, step + q, 0.0, nodes[q - 1], h, guard, False) if q > 0 else None
    if got is None:
        raise Unsure("a contact change the bracketing lost")
    return nodes[:q], idx[:q], np.zeros(q), (step + q, got[0], got[1])


def rise(fn: Callable[[np.ndarray], np.ndarray], lo: float, hi: float) -> float:
    """The angle (rad) in [lo, hi] where ``fn`` (of angles, on the host), below zero at ``lo``, first rises above
    it: as :func:`cross`, the span cut in 64 twice over, the root interpolated across the last cut."""
    for _ in range(2):
        ts = np.linspace(lo, hi, _SPLIT + 1)
        vals = fn(ts)
        i = int(np.argmax(vals > 0.0))
        lo, hi = ts[i - 1], ts[i]
    f = min(max(vals[i - 1] / (vals[i - 1] - vals[i]), 0.0), 1.0)
    return lo + f * (hi - lo)


def step_bounds(f: np.ndarray) -> np.ndarray:
    """Bounds below a force sampled on the fine nodes, one per step between them: the step's lower end less twice
    the reach of its convexity (a second difference over 8), the least of the four second differences about the
    step (a jump at a segment's boundary is not a curvature)."""
    if f.size < 4:
        return np.minimum(f[:-1], f[1:])
    d2 = np.diff(f, 2)
    curv = np.concatenate([d2[:1], d2, d2[-1:]])  # per node
    pad = np.concatenate([curv[:1], curv, curv[-1:]])  # per node, one more each side
    convex = np.maximum(0.0, np.min(np.stack([pad[:-3], pad[1:-2], pad[2:-1], pad[3:]]), axis=0))  # per step
    return np.minimum(f[:-1], f[1:]) - 0.25 * convex


def lower_bound(f: np.ndarray) -> float:
    """A bound below a force sampled on the fine nodes, between them too (:func:`step_bounds`' least)."""
    if f.size < 2:
        return float(np.min(f)) if f.size else math.inf
    return float(np.min(step_bounds(f)))
