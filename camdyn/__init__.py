"""camdyn: cam mechanism synthesis, geometry and follower dynamics; prove the follower never leaves the cam.

The public API is flat (``camdyn.load_case``, ``camdyn.run_check``, ``camdyn.size_spring``, ...); each name
loads its module on first use, so ``import camdyn`` stays cheap (no JAX) and the command line answers at once.
The house, one way through: :mod:`camdyn.schema` (the case-file schema) -> :mod:`camdyn.model` (SI models:
motion, geometry, dynamics, linkages) -> :mod:`camdyn.design` (checks, sizing, sweeps, synthesis) ->
:mod:`camdyn.plot` and :mod:`camdyn.report` -> :mod:`camdyn.cli`.
"""

from importlib import import_module

_API = {
    # errors
    "CamdynError": "._core.errors",
    "InputError": "._core.errors",
    "NumericalError": "._core.errors",
    "enable_x64": "._core.precision",
    # schema
    "CaseSpec": ".schema",
    "FollowerSpec": ".schema",
    "PathFileSpec": ".schema",
    "load_case_spec": ".schema",
    "SpringSpec": ".schema",
    "MaterialsSpec": ".schema",
    "DriveSpec": ".schema",
    # models
    "LAWS": ".model.motion",
    "Motion": ".model.motion",
    "Program": ".model.motion",
    "Segment": ".model.motion",
    "HermiteMotion": ".model.motion",
    "law": ".model.motion",
    "evaluate": ".model.motion",
    "FollowerModel": ".model.follower",
    "Case": ".model.case",
    "load_case": ".model.case",
    "case_from_dict": ".model.case",
    "CamGeometry": ".model.geometry",
    "analyze": ".model.geometry",
    "lever_arm_mm": ".model.geometry",
    "Response": ".model.dynamics",
    "Separation": ".model.dynamics",
    "kinematic_force": ".model.dynamics",
    "kinematic_jump_speed": ".model.dynamics",
    "dynamic_jump_speed": ".model.dynamics",
    "response": ".model.dynamics",
    "with_spring_mass": ".model.follower",
    "DriveTorque": ".model.drive",
    "kinematic_drive": ".model.drive",
    "response_drive": ".model.drive",
    "ContactStress": ".model.contact",
    "cam_contact": ".model.contact",
    "HelicalSpring": ".model.spring",
    "chain_jump_speed": ".model.surge",
    "Synthesis": ".model.linkage",
    "synthesize_motion": ".model.linkage",
    # design
    "Check": ".design._check",
    "CheckKind": ".design._check",
    "CheckReport": ".design.checks",
    "run_check": ".design.checks",
    "judge_geometry": ".design.geometry",
    "min_base_radius": ".design.geometry",
    "motion_table": ".design.table",
    "SpringSizing": ".design.sizing",
    "size_spring": ".design.sizing",
    "JumpMap": ".design.sweep",
    "jump_map": ".design.sweep",
    "synthesize_dimensions": ".design.synthesis",
    "synthesize_case": ".design.synthesis",
    "optimize_case": ".design.optimize",
    "SpringDesign": ".design.spring",
    "design_spring": ".design.spring",
    "design_case_spring": ".design.spring",
    "case_drive": ".design.parts",
    "case_contact": ".design.parts",
    "spring_jump_speed": ".design.parts",
    "MachineResult": ".design.machine",
    "check_machine": ".design.machine",
    "run_machine": ".design.machine",
    "load_machine": ".schema.machine",
    "MachineSpec": ".schema.machine",
    # figures, reports, files
    "plot_feasible_region": ".plot",
    "plot_jump_map": ".plot",
    "write_report": ".report",
    "write_profile": ".export",
    "write_machine_report": ".report.machine",
}

__all__ = sorted(_API)  # pyright: ignore[reportUnsupportedDunderAll]  (the stub __init__.pyi lists it for editors)


def __getattr__(name: str):
    if name in _API:
        return getattr(import_module(_API[name], __name__), name)
    raise AttributeError(f"module 'camdyn' has no attribute {name!r}")


def __dir__():
    return __all__
