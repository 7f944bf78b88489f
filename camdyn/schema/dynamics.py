"""The ``[dynamics]`` table: speed, moving mass, spring, damping, follower train, restitution, external load.

Translating followers use the linear keys (kg, N/mm, N, N*s/m), oscillating followers the rotational ones
(kg*m^2, N*m/rad, N*m, N*m*s/rad); :data:`LINEAR_KEYS` and :data:`ROTARY_KEYS` pair them up.
"""

from __future__ import annotations

from pydantic import Field, model_validator

from .._core.kinds import FollowerKind
from .._core.units import (
    DEFAULT_TRAIN_DAMPING_RATIO,
    INERTIA_RANGE_KG_M2,
    MASS_RANGE_KG,
    MAX_DAMPING,
    MAX_DAMPING_RATIO,
    MAX_FORCE_N,
    MAX_RATE_N_PER_MM,
    MAX_SPEED_RPM,
    MAX_TORQUE_N_M,
    MAX_TORSION_RATE_N_M_PER_RAD,
)
from ._base import Real, Table

# the linear key and its rotational counterpart, in pairs
LINEAR_KEYS = ("mass", "spring_rate", "preload", "train_stiffness", "external_force")
ROTARY_KEYS = ("inertia", "torsion_rate", "preload_torque", "train_torsion_rate", "external_torque")


class DynamicsSpec(Table):
    """The ``[dynamics]`` table. Translating followers use the linear keys, oscillating the rotational ones."""

    speed: Real = Field(gt=0, le=MAX_SPEED_RPM, description="cam speed, rpm (at most 1e5)")
    # translating follower
    mass: Real | None = Field(
        default=None,
        ge=MASS_RANGE_KG[0],
        le=MASS_RANGE_KG[1],
        description="translating: equivalent moving mass, kg (1e-6 to 1e4)",
    )
    spring_rate: Real | None = Field(
        default=None, gt=0, le=MAX_RATE_N_PER_MM, description="translating: return spring rate k, N/mm (at most 1e7)"
    )
    preload: Real | None = Field(
        default=None,
        ge=-MAX_FORCE_N,
        le=MAX_FORCE_N,
        description="translating: spring force at zero lift F0, N (|F0| at most 1e7)",
    )
    train_stiffness: Real | None = Field(
        default=None,
        gt=0,
        le=10 * MAX_RATE_N_PER_MM,
        description=(
            "translating: follower-train (contact) stiffness k_f, N/mm (at most 1e8); omit for a rigid follower"
        ),
    )
    external_force: Real = Field(
        default=0.0,
        ge=-MAX_FORCE_N,
        le=MAX_FORCE_N,
        description="translating: constant force pushing the follower onto the cam (weight, process load), N",
    )
    # oscillating follower (rotational equivalent)
    inertia: Real | None = Field(
        default=None,
        ge=INERTIA_RANGE_KG_M2[0],
        le=INERTIA_RANGE_KG_M2[1],
        description="oscillating: arm inertia about its pivot, kg*m^2 (1e-12 to 1e4)",
    )
    torsion_rate: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_TORSION_RATE_N_M_PER_RAD,
        description="oscillating: return torsion spring rate, N*m/rad (at most 1e7)",
    )
    preload_torque: Real | None = Field(
        default=None,
        ge=-MAX_TORQUE_N_M,
        le=MAX_TORQUE_N_M,
        description="oscillating: spring torque at zero swing, N*m (|T0| at most 1e6)",
    )
    train_torsion_rate: Real | None = Field(
        default=None,
        gt=0,
        le=10 * MAX_TORSION_RATE_N_M_PER_RAD,
        description="oscillating: follower-train stiffness, N*m/rad (at most 1e8); omit for a rigid follower",
    )
    external_torque: Real = Field(
        default=0.0,
        ge=-MAX_TORQUE_N_M,
        le=MAX_TORQUE_N_M,
        description="oscillating: constant torque pushing the arm onto the cam, N*m",
    )
    # both
    damping_ratio: Real | None = Field(
        default=None, ge=0, le=MAX_DAMPING_RATIO, description="zeta: c = 2 zeta sqrt(k m) (give this or damping)"
    )
    damping: Real | None = Field(
        default=None, ge=0, le=MAX_DAMPING, description="c, N*s/m (N*m*s/rad for an oscillating arm)"
    )
    train_damping_ratio: Real = Field(
        default=DEFAULT_TRAIN_DAMPING_RATIO,
        ge=0,
        le=MAX_DAMPING_RATIO,
        description="zeta_f: c_f = 2 zeta_f sqrt(k_f m)",
    )
    restitution: Real = Field(
        default=0.0, ge=0, le=1, description="coefficient of restitution at re-contact after a jump, 0..1"
    )

    @model_validator(mode="after")
    def _one_damping(self) -> DynamicsSpec:
        if self.damping_ratio is not None and self.damping is not None:
            raise ValueError("give damping_ratio or damping, not both")
        return self

    def generalized(self, kind: FollowerKind) -> tuple[float | None, float | None, float | None, float | None, float]:
        """(mass, rate, preload, train rate, external load) in the case file's units of ``kind`` (None: not given)."""
        return tuple(getattr(self, k) for k in dynamics_keys(kind))


def dynamics_keys(kind: FollowerKind) -> tuple[str, ...]:
    """The keys ``kind`` uses, in :data:`LINEAR_KEYS` order: mass, rate, preload, train rate, external load."""
    return ROTARY_KEYS if kind.rotary else LINEAR_KEYS


def check_dynamics_keys(
    d: DynamicsSpec, *, kind: FollowerKind, key: str = "dynamics", form_closed: bool = False
) -> None:
    """Raise ``ValueError("<key>.<name>: message")`` unless ``d`` uses the keys of its follower kind: the linear
    ones for a translating follower, the rotational ones for an oscillating arm (mass, rate and preload needed;
    a form-closed follower needs only the mass: its spring rate and preload default to 0)."""
    use = dynamics_keys(kind)
    other = LINEAR_KEYS if use is ROTARY_KEYS else ROTARY_KEYS
    for k_use, k_other in zip(use, other, strict=True):
        given = getattr(d, k_other)
        if given is not None and (k_other not in ("external_force", "external_torque") or given != 0.0):
            raise ValueError(f"{key}.{k_other}: {kind.a} follower uses {k_use}, not {k_other}")
    for k in use[:1] if form_closed else use[:3]:
        if getattr(d, k) is None:
            raise ValueError(f"{key}.{k}: required key is missing")
