"""Type stub of the flat, lazily loaded public API (``camdyn/__init__.py``): what an editor and a type checker
see. ``tests/test_api.py`` checks that it names exactly ``camdyn.__all__``, each from its module."""

from ._core.errors import (
    CamdynError as CamdynError,
    InputError as InputError,
    NumericalError as NumericalError,
)
from ._core.precision import enable_x64 as enable_x64
from .schema import (
    CaseSpec as CaseSpec,
    DriveSpec as DriveSpec,
    FollowerSpec as FollowerSpec,
    MaterialsSpec as MaterialsSpec,
    PathFileSpec as PathFileSpec,
    SpringSpec as SpringSpec,
    load_case_spec as load_case_spec,
)
from .model.motion import (
    HermiteMotion as HermiteMotion,
    LAWS as LAWS,
    Motion as Motion,
    Program as Program,
    Segment as Segment,
    evaluate as evaluate,
    law as law,
)
from .model.follower import FollowerModel as FollowerModel, with_spring_mass as with_spring_mass
from .model.case import (
    Case as Case,
    case_from_dict as case_from_dict,
    load_case as load_case,
)
from .model.geometry import (
    CamGeometry as CamGeometry,
    analyze as analyze,
    lever_arm_mm as lever_arm_mm,
)
from .model.dynamics import (
    Response as Response,
    Separation as Separation,
    dynamic_jump_speed as dynamic_jump_speed,
    kinematic_force as kinematic_force,
    kinematic_jump_speed as kinematic_jump_speed,
    response as response,
)
from .model.drive import (
    DriveTorque as DriveTorque,
    kinematic_drive as kinematic_drive,
    response_drive as response_drive,
)
from .model.contact import ContactStress as ContactStress, cam_contact as cam_contact
from .model.spring import HelicalSpring as HelicalSpring
from .model.surge import chain_jump_speed as chain_jump_speed
from .model.linkage import Synthesis as Synthesis, synthesize_motion as synthesize_motion
from .design._check import Check as Check, CheckKind as CheckKind
from .design.checks import CheckReport as CheckReport, run_check as run_check
from .design.geometry import judge_geometry as judge_geometry, min_base_radius as min_base_radius
from .design.table import motion_table as motion_table
from .design.sizing import SpringSizing as SpringSizing, size_spring as size_spring
from .design.sweep import JumpMap as JumpMap, jump_map as jump_map
from .design.synthesis import synthesize_case as synthesize_case, synthesize_dimensions as synthesize_dimensions
from .design.optimize import optimize_case as optimize_case
from .design.spring import (
    SpringDesign as SpringDesign,
    design_case_spring as design_case_spring,
    design_spring as design_spring,
)
from .design.parts import (
    case_contact as case_contact,
    case_drive as case_drive,
    spring_jump_speed as spring_jump_speed,
)
from .design.machine import (
    MachineResult as MachineResult,
    check_machine as check_machine,
    run_machine as run_machine,
)
from .schema.machine import MachineSpec as MachineSpec, load_machine as load_machine
from .plot import plot_feasible_region as plot_feasible_region, plot_jump_map as plot_jump_map
from .report import write_report as write_report
from .export import write_profile as write_profile
from .report.machine import write_machine_report as write_machine_report

__all__: list[str]
