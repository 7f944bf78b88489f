"""The time-domain follower models' diffrax settings (compliant shooting and rigid flights share them)."""

RTOL, ATOL = 1e-9, 1e-10  # the step-size controller's tolerances (motion units: mm or rad)
# The compliant shooting where its orbit is smooth (the follower on the cam all the way round) takes Dopri8 at a
# hundredth of them: as close to a reference at rtol 1e-13 as Tsit5 at RTOL (the lecture's orbit within 1.4e-9 mm
# against 1.5e-9 mm), in 1.1-1.6 times less time. Where the follower leaves the cam, Tsit5 at RTOL: Dopri8 steps
# through the contact switches at twice its cost.
SMOOTH_RTOL, SMOOTH_ATOL = RTOL / 100, ATOL / 100
MAX_STEPS = 200_000  # per solve: far more than a revolution takes unless the train is far too stiff to resolve
