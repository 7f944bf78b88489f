"""The worst samples as case files a user can ``check``: the case's own tables with the sample's spring rate,
preload, mass, train stiffness and speed in ``[dynamics]`` (the damping keeps its ratio, as in the study).

A sample's profile error is not a case-file key: the file has the nominal profile, and its header gives the
error's RMS (the least force and jump speed in the header are the sample's, with the error)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...schema import LINEAR_KEYS, dynamics_keys, read_toml
from ._result import ToleranceResult
from ._valvetrain import ValveToleranceResult

if TYPE_CHECKING:
    from ...model.case import Case


def worst_case_docs(case: Case, result: ToleranceResult) -> list[tuple[dict, list[str]]]:
    """Per worst sample (least contact force first): the case as a TOML document and its header lines."""
    raw = read_toml(case.source) if case.source is not None else case.spec.model_dump(mode="json", exclude_none=True)
    raw.pop("tolerances", None)
    names = dict(zip(LINEAR_KEYS, dynamics_keys(case.kind), strict=True))  # a translating key -> the kind's
    out = []
    for rank, i in enumerate(result.worst, start=1):
        doc = {**raw, "name": f"{case.name}-worst-{rank}", "dynamics": dict(raw["dynamics"])}
        for key in ("spring_rate", "preload", "mass", "train_stiffness"):
            name = names[key]
            if key != "train_stiffness" or name in doc["dynamics"]:
                doc["dynamics"][name] = float(result.params[key][i])
        doc["dynamics"]["speed"] = float(result.params["speed"][i])
        header = [
            f"camdyn tolerance: sample {i} of {result.samples} (seed {result.seed}) of case {case.name!r}, worst "
            f"{rank} by least contact force",
            f"with its profile error (RMS {result.params['profile_error'][i]:.4g} "
            f"{case.kind.motion_unit}, not in this file): least contact force "
            f"{result.least_force[i]:.6g} N, dynamic jump speed {result.jump_speed_rpm[i]:.6g} rpm",
        ]
        out.append((doc, header))
    return out


def worst_valvetrain_docs(case: Case, result: ValveToleranceResult) -> list[tuple[dict, list[str]]]:
    """Per worst built valvetrain (the lowest of its float and bounce speeds first): the case as a TOML document
    with the sample's valve spring, speed, cam contact and ``[valvetrain]`` values, and its header lines."""
    raw = read_toml(case.source) if case.source is not None else case.spec.model_dump(mode="json", exclude_none=True)
    raw.pop("tolerances", None)
    out = []
    for rank, i in enumerate(result.worst, start=1):
        doc = {**raw, "name": f"{case.name}-worst-{rank}"}
        doc["dynamics"], doc["valvetrain"] = dict(raw["dynamics"]), dict(raw["valvetrain"])
        for key in ("spring_rate", "preload", "speed", "train_stiffness"):
            if key != "train_stiffness" or key in doc["dynamics"]:
                doc["dynamics"][key] = float(result.params[key][i])
        for key in ("lash", "cam_side_mass", "valve_mass"):
            doc["valvetrain"][key] = float(result.params[key][i])
        if "stiffness" in doc["valvetrain"]:
            doc["valvetrain"]["stiffness"] = float(result.params["valvetrain_stiffness"][i])
        header = [
            f"camdyn tolerance: sample {i} of {result.samples} (seed {result.seed}) of case {case.name!r}, worst "
            f"{rank} by the lower of its float and bounce speeds",
            f"float speed {result.float_speed_rpm[i]:.6g} rpm, bounce speed {result.bounce_speed_rpm[i]:.6g} rpm "
            "(local searches about the nominal's)",
        ]
        out.append((doc, header))
    return out
