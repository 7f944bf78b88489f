"""Spring sizing: the return spring with the least peak force that keeps the follower on the cam.

**Problem.** Choose the spring rate k and preload F0 so that the interface force stays at or above
``[limits] min_contact_force`` (F_min) at every cam angle and every cam speed w in [0, W], W = margin * the
maximum speed, with the least peak spring force ``P = max_theta (k s + F0) = k s_max + F0`` (it drives the cam
stress, the wear and the drive torque). k >= ``min_rate`` (default 0); F0 is free.

**Kinematic answer (linear program).** The interface force of a follower that stays on the cam,
``Fi(theta, w) = m w^2 s'' + c w s' + k s + F0 + F_ext``, is linear in (k, F0) at every angle and speed. At each
angle it is a quadratic in w, so its least value over [0, W] is closed form: at w = 0, at w = W, or at the vertex
w = -c s' / (2 m s'') where m s'' > 0 > c s'. So every angle gives one constraint, exact for all speeds at once:
``s_i k + F0 >= r_i``, ``r_i = F_min - F_ext - min_w (m w^2 s''_i + c w s'_i)``. On 3600 angles (and both sides
of every segment boundary) this is a linear program in (k, F0), solved by HiGHS (:mod:`camdyn._core.linprog`);
the angles between grid points where the answer would be violated are found by local minimization and added as
cutting planes until none is violated by more than 1e-9 of the force scale.

**Ties.** With c constant the peak force ``P(k) = max_i (r_i + k (s_max - s_i))`` never decreases with k
(F0 >= r_i - k s_i and s_i <= s_max), so the least rate attains the least peak force P* = P(k_lo); with
k_lo = 0 that is a constant-force spring. A rate only costs peak force, by k (s_max - s_bind), unless the binding
angle is at full lift; then the optimum is the segment k in [k_lo, k_end] of the line k s_max + F0 = P*,
``k_end = min over s_i < s_max of (P* - r_i) / (s_max - s_i)`` (the eccentric cam is the example). Ties are
broken towards the least preload: k_end, the stiffest optimal spring, which also has the least mean spring force
over the revolution (``k mean(s) + F0 = P - k (s_max - mean(s))``); it is what a second, lexicographic LP
minimizing F0 at P* returns, computed in closed form (no LP tolerance), and the LP's P* is checked against the
closed form. ``min_rate`` bounds k from below: a real spring has a rate, and with the rate you have the answer
is the least preload for it. With constant damping a binding angle next to full lift, on a flank where the
follower moves, is not at full lift: the rate costs peak force there (the LP's closed form gives k_end = k_lo).

**Damping.** ``damping`` (N*s/m) is a constant c and the LP above is exact. With ``damping_ratio``,
c = 2 zeta sqrt(k m) depends on k; then for each k the least preload is still closed form,
``F0(k) = max_i (r_i(sqrt k) - k s_i)``, and the peak force ``P = k s_max + F0(k)`` is convex in u = sqrt(k)
(r_i is the maximum over w of functions affine in u, and (s_max - s_i) u^2 is convex), so it is minimized exactly
in u (bounded Brent), with the same tie-break (the largest k whose peak force is within 1e-11 of the least).
A binding angle at full lift is then no tie by itself: c grows with k, and where the follower leaves full lift
next to the binding angle (s' < 0 on the flank after a top, where the damper pulls it off the cam) the binding
moves onto that flank as soon as c > 0, so every rate costs peak force (about c^2, i.e. linear in k). Where the
least rate reaches the least peak force and the peak force rises from it, the answer is the least rate, exactly;
the rise is judged at the k-midpoint of the stretch the 1e-11 walk found, with the preload held between grid
angles too (on the grid alone the rise is far slower, and the walk would stop at a rate the tolerance and the
cutting-plane rounds make).
(Freezing c at one value and iterating the LP to a fixed point does not find this optimum: with c frozen the LP
puts k at 0, where c = 0, although a little damping on a rising binding angle lowers the requirement like sqrt k.)

**Dynamic correction.** A compliant follower train (``train_stiffness``) jumps below its kinematic jump speed,
so the kinematic answer can fail at W. In contact the model is linear, and its steady state is exact in the
frequency domain (:func:`camdyn.model.dynamics.linear_contact_force`); the preload only shifts its mean:
``Fc(theta, w; k, F0) = alpha F0 + G(theta, w; k)``, alpha = k_f / (k + k_f). So for each k the least preload is
exact, ``F0_dyn(k) = max over theta and w of (F_min - G) / alpha``, with w on 0 and 160 speeds up to W refined
twice around the worst. The dynamic peak force ``k s_max + F0_dyn(k)`` is minimized over k (scan in sqrt k from
min_rate to the rate beyond which even the static requirement at least lift costs more than the kinematic
answer does dynamically, then bounded Brent around the best), ties within 1e-6 broken the same way (largest k,
and the least rate where the peak force rises from it).
The answer is then verified on 1127 speeds in [0, W] and F0 raised by any remaining deficit / alpha. Rigid
followers: the dynamic interface force is the kinematic one, and the kinematic answer is the answer.

**Oscillating followers** are sized in their rotational units: torsion rate (N*m/rad), preload torque (N*m),
peak spring torque (N*m); the contact force limit F_min (N) becomes the torque ``F_min * lever_arm(theta)`` at
each angle (the same conversion ``check`` uses), which keeps every constraint linear.

Modules: :mod:`._problem` (the problem and its angle grid, immutable), :mod:`._kinematic` (the requirement per
angle, the least preload per rate, where it binds), :mod:`._lp` (the LP with its cutting planes and tie-break),
:mod:`._sqrt_k` (damping that follows the rate: the search in sqrt k), :mod:`._dynamic` (the dynamic
correction), :mod:`._design` (what one spring does), :mod:`._results` (the result types and their JSON),
:mod:`._size` (:func:`size_spring`), :mod:`._valvetrain` (:func:`size_valve_spring`: a valvetrain's valve spring,
from the equivalent follower's closed form to the two-mass model's float and bounce speeds).
"""

from ._results import TIE_BREAK, SpringDesign, SpringSizing
from ._size import size_spring
from ._valvetrain import ValveSpringDesign, ValveSpringSizing, size_valve_spring

__all__ = [
    "TIE_BREAK",
    "SpringDesign",
    "SpringSizing",
    "ValveSpringDesign",
    "ValveSpringSizing",
    "size_spring",
    "size_valve_spring",
]
