"""The public API is a contract (as pyhf pins its own): a name leaves or arrives only with this list changed."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from importlib import import_module
from pathlib import Path

import pytest

import camdyn

PUBLIC = [
    "CamGeometry",
    "CamdynError",
    "Case",
    "CaseSpec",
    "Check",
    "CheckKind",
    "CheckReport",
    "ContactStress",
    "DriveSpec",
    "DriveTorque",
    "FollowerModel",
    "FollowerSpec",
    "HelicalSpring",
    "HermiteMotion",
    "InputError",
    "JumpMap",
    "LAWS",
    "MachineResult",
    "MachineSpec",
    "MaterialsSpec",
    "Motion",
    "NumericalError",
    "PathFileSpec",
    "Program",
    "Response",
    "Segment",
    "Separation",
    "SpringDesign",
    "SpringSizing",
    "SpringSpec",
    "Synthesis",
    "analyze",
    "cam_contact",
    "case_contact",
    "case_drive",
    "case_from_dict",
    "chain_jump_speed",
    "check_machine",
    "design_case_spring",
    "design_spring",
    "dynamic_jump_speed",
    "enable_x64",
    "evaluate",
    "judge_geometry",
    "jump_map",
    "kinematic_drive",
    "kinematic_force",
    "kinematic_jump_speed",
    "law",
    "lever_arm_mm",
    "load_case",
    "load_case_spec",
    "load_machine",
    "min_base_radius",
    "motion_table",
    "optimize_case",
    "plot_feasible_region",
    "plot_jump_map",
    "response",
    "response_drive",
    "run_check",
    "run_machine",
    "size_spring",
    "spring_jump_speed",
    "synthesize_case",
    "synthesize_dimensions",
    "synthesize_motion",
    "with_spring_mass",
    "write_machine_report",
    "write_profile",
    "write_report",
]


def test_the_public_api_is_pinned():
    assert sorted(camdyn.__all__) == PUBLIC


def test_every_public_name_loads():
    for name in PUBLIC:
        assert getattr(camdyn, name) is not None, name


def test_the_type_stub_names_each_public_name_from_its_module():
    """``camdyn/__init__.pyi`` (what an editor sees of the lazy API) re-exports exactly the runtime names."""
    tree = ast.parse((Path(camdyn.__file__).parent / "__init__.pyi").read_text())
    stub = {}
    for node in tree.body:
        if isinstance(node, ast.ImportFrom):
            for alias in node.names:
                assert alias.asname == alias.name, alias.name  # an explicit re-export
                stub[alias.name] = "." * node.level + (node.module or "")
    assert stub == camdyn._API
    for name, module in stub.items():
        assert hasattr(import_module(module, "camdyn"), name), name


@pytest.mark.slow  # a fresh Python loading JAX and a case (3 s)
def test_the_library_changes_no_global_setting_and_refuses_float32():
    """Importing camdyn's models leaves JAX's 64-bit mode alone (as diffrax does); building a case without it is
    refused in one line rather than computed in float32."""

    code = (
        "import jax, camdyn\nimport camdyn.model.case\nprint(jax.config.jax_enable_x64)\n"
        "try:\n    camdyn.load_case('cases/lecture.toml')\nexcept camdyn.CamdynError as e:\n    print(e)\n"
        "camdyn.enable_x64()\nprint(camdyn.load_case('cases/lecture.toml').name)"
    )
    root = Path(camdyn.__file__).resolve().parents[1]
    env = {k: v for k, v in os.environ.items() if k != "JAX_ENABLE_X64"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=root, env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.strip().splitlines()
    assert lines[0] == "False"
    assert lines[1].startswith("camdyn computes in float64")
    assert lines[-1] == "lecture"
