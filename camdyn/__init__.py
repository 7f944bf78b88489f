"""camdyn: cam mechanism synthesis, geometry and follower dynamics; prove the follower never leaves the cam.

The public API is flat (``camdyn.Program``, ``camdyn.load_case``, ``camdyn.run_check``, ...). Submodules load
on first use, so ``import camdyn`` stays cheap and the command line can configure JAX and equinox first.
"""

from importlib import import_module

import jax

jax.config.update("jax_enable_x64", True)

_API = {
    "CamdynError": "errors",
    "InputError": "errors",
    "NumericalError": "errors",
    "LAWS": "motion",
    "Motion": "motion",
    "Program": "motion",
    "Segment": "motion",
    "HermiteMotion": "motion",
    "law": "motion",
    "evaluate": "motion",
    "FollowerModel": "dynamics",
    "Response": "dynamics",
    "Separation": "dynamics",
    "kinematic_force": "dynamics",
    "kinematic_jump_speed": "dynamics",
    "dynamic_jump_speed": "dynamics",
    "response": "dynamics",
    "Case": "case",
    "load_case": "case",
    "Check": "checks",
    "CheckReport": "checks",
    "run_check": "checks",
    "FollowerSpec": "geometry",
    "min_base_radius": "geometry",
    "Synthesis": "linkage",
    "synthesize_motion": "linkage",
    "synthesize_dimensions": "linkage",
    "SpringSizing": "sizing",
    "size_spring": "sizing",
    "plot_feasible_region": "sizing",
    "JumpMap": "sweep",
    "jump_map": "sweep",
    "plot_jump_map": "sweep",
    "write_report": "report",
    "write_profile": "export",
}

__all__ = sorted(_API)


def __getattr__(name: str):
    if name in _API:
        return getattr(import_module(f".{_API[name]}", __name__), name)
    raise AttributeError(f"module 'camdyn' has no attribute {name!r}")
