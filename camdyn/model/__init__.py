"""SI models built once from a validated case: the follower motion, the cam geometry, the follower dynamics
and the cam-linkage syntheses. Importing it switches JAX to float64, which every model relies on."""

import jax

jax.config.update("jax_enable_x64", True)
