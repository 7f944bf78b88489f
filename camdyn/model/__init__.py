"""SI models built once from a validated case: the follower motion, the cam geometry, the follower dynamics
and the cam-linkage syntheses. They compute in float64: the caller switches JAX's 64-bit mode on
(:func:`camdyn.enable_x64`); :func:`camdyn.model.case.build_case` refuses to build a case without it."""
