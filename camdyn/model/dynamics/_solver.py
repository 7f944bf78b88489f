"""The time-domain follower models' diffrax settings (compliant shooting and rigid flights share them)."""

RTOL, ATOL = 1e-9, 1e-10  # the step-size controller's tolerances (motion units: mm or rad)
MAX_STEPS = 200_000  # per solve: far more than a revolution takes unless the train is far too stiff to resolve
