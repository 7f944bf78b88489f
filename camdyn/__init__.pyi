"""Type stub of the flat, lazily loaded public API (``camdyn/__init__.py``): what an editor and a type checker
see. ``tests/test_api.py`` checks that it names exactly ``camdyn.__all__``, each from its module."""

from ._core.errors import (
    CamdynError as CamdynError,
)
from ._core.errors import (
    InputError as InputError,
)
from ._core.errors import (
    NumericalError as NumericalError,
)
from ._core.precision import enable_x64 as enable_x64
from .design._check import Check as Check
from .design._check import CheckKind as CheckKind
from .design.checks import CheckReport as CheckReport
from .design.checks import run_check as run_check
from .design.geometry import judge_geometry as judge_geometry
from .design.geometry import min_base_radius as min_base_radius
from .design.machine import (
    MachineResult as MachineResult,
)
from .design.machine import (
    check_machine as check_machine,
)
from .design.machine import (
    run_machine as run_machine,
)
from .design.optimize import optimize_case as optimize_case
from .design.parts import (
    case_contact as case_contact,
)
from .design.parts import (
    case_drive as case_drive,
)
from .design.parts import (
    spring_jump_speed as spring_jump_speed,
)
from .design.sizing import SpringSizing as SpringSizing
from .design.sizing import size_spring as size_spring
from .design.spring import (
    SpringDesign as SpringDesign,
)
from .design.spring import (
    design_case_spring as design_case_spring,
)
from .design.spring import (
    design_spring as design_spring,
)
from .design.sweep import JumpMap as JumpMap
from .design.sweep import jump_map as jump_map
from .design.synthesis import synthesize_case as synthesize_case
from .design.synthesis import synthesize_dimensions as synthesize_dimensions
from .design.table import motion_table as motion_table
from .export import write_profile as write_profile
from .model.case import (
    Case as Case,
)
from .model.case import (
    case_from_dict as case_from_dict,
)
from .model.case import (
    load_case as load_case,
)
from .model.contact import ContactStress as ContactStress
from .model.contact import cam_contact as cam_contact
from .model.drive import (
    DriveTorque as DriveTorque,
)
from .model.drive import (
    kinematic_drive as kinematic_drive,
)
from .model.drive import (
    response_drive as response_drive,
)
from .model.dynamics import (
    Response as Response,
)
from .model.dynamics import (
    Separation as Separation,
)
from .model.dynamics import (
    dynamic_jump_speed as dynamic_jump_speed,
)
from .model.dynamics import (
    kinematic_force as kinematic_force,
)
from .model.dynamics import (
    kinematic_jump_speed as kinematic_jump_speed,
)
from .model.dynamics import (
    response as response,
)
from .model.follower import FollowerModel as FollowerModel
from .model.follower import with_spring_mass as with_spring_mass
from .model.geometry import (
    CamGeometry as CamGeometry,
)
from .model.geometry import (
    analyze as analyze,
)
from .model.geometry import (
    lever_arm_mm as lever_arm_mm,
)
from .model.linkage import Synthesis as Synthesis
from .model.linkage import synthesize_motion as synthesize_motion
from .model.motion import (
    LAWS as LAWS,
)
from .model.motion import (
    HermiteMotion as HermiteMotion,
)
from .model.motion import (
    Motion as Motion,
)
from .model.motion import (
    Program as Program,
)
from .model.motion import (
    Segment as Segment,
)
from .model.motion import (
    evaluate as evaluate,
)
from .model.motion import (
    law as law,
)
from .model.spring import HelicalSpring as HelicalSpring
from .model.surge import chain_jump_speed as chain_jump_speed
from .plot import plot_feasible_region as plot_feasible_region
from .plot import plot_jump_map as plot_jump_map
from .report import write_report as write_report
from .report.machine import write_machine_report as write_machine_report
from .schema import (
    CaseSpec as CaseSpec,
)
from .schema import (
    DriveSpec as DriveSpec,
)
from .schema import (
    FollowerSpec as FollowerSpec,
)
from .schema import (
    MaterialsSpec as MaterialsSpec,
)
from .schema import (
    PathFileSpec as PathFileSpec,
)
from .schema import (
    SpringSpec as SpringSpec,
)
from .schema import (
    load_case_spec as load_case_spec,
)
from .schema.machine import MachineSpec as MachineSpec
from .schema.machine import load_machine as load_machine

__all__: list[str]
