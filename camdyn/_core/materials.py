"""Material data: the elastic constants of cam and follower materials, and the spring wires with their strength
against wire diameter. Plain data (no numpy, no JAX): the schema validates names against it, the models read
the numbers. Every number cites its table.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from difflib import get_close_matches

# Shigley's Mechanical Engineering Design (10th ed.), Table A-5: modulus of elasticity E (GPa), Poisson's ratio
ELASTIC: dict[str, tuple[float, float]] = {
    "steel": (207.0, 0.292),  # carbon steel
    "stainless-steel": (190.0, 0.305),  # 18-8
    "cast-iron": (100.0, 0.211),  # gray
    "aluminium": (71.0, 0.333),
    "bronze": (111.0, 0.349),  # phosphor bronze
    "brass": (106.0, 0.324),
}
GPA = 1e9  # Pa per GPa
MPA = 1e6  # Pa per MPa


@dataclass(frozen=True)
class WireMaterial:
    """A spring wire: minimum tensile strength Sut = A / d^m (MPa, d in mm) in diameter bands, the moduli, the
    density and the torsional yield strength as a fraction of Sut.

    Sources, Shigley's Mechanical Engineering Design (10th ed.): Table 10-4 (A, m and the diameter bands),
    Table 10-5 (E, G; music wire's by diameter), Table 10-6 (the static torsional yield, before set removal, with
    the Bergstrasser factor: 45 % of Sut for music wire, 50 % for hardened and tempered carbon and low-alloy
    steel, 35 % for austenitic stainless). The density is Shigley's 0.284 lbf/in^3 for the steels (Example 10-4)
    and 0.286 lbf/in^3 for 302 stainless.
    """

    name: str
    astm: str
    bands: tuple[tuple[float, float, float, float], ...]  # (d_min mm, d_max mm, m, A MPa*mm^m)
    E_bands: tuple[tuple[float, float], ...]  # (d_max mm, E GPa): the first band with d <= d_max applies
    G_bands: tuple[tuple[float, float], ...]  # (d_max mm, G GPa)
    density_kg_m3: float
    yield_fraction: float  # Ssy / Sut, static, before set removal
    relative_cost: float  # Table 10-4

    @property
    def d_range_mm(self) -> tuple[float, float]:
        return self.bands[0][0], self.bands[-1][1]


_INF = float("inf")
WIRES: dict[str, WireMaterial] = {
    "music-wire": WireMaterial(
        "music-wire",
        "A228",
        ((0.10, 6.5, 0.145, 2211.0),),
        ((0.8, 203.4), (1.61, 200.0), (3.18, 198.2), (_INF, 196.5)),
        ((0.8, 82.7), (1.61, 81.7), (3.18, 81.0), (_INF, 80.0)),
        7860.0,
        0.45,
        2.6,
    ),
    "oil-tempered": WireMaterial(
        "oil-tempered", "A229", ((0.5, 12.7, 0.187, 1855.0),), ((_INF, 196.5),), ((_INF, 77.2),), 7860.0, 0.50, 1.3
    ),
    "chrome-silicon": WireMaterial(
        "chrome-silicon", "A401", ((1.6, 9.5, 0.108, 1974.0),), ((_INF, 203.4),), ((_INF, 77.2),), 7860.0, 0.50, 4.0
    ),
    "stainless-302": WireMaterial(
        "stainless-302",
        "A313",
        ((0.3, 2.5, 0.146, 1867.0), (2.5, 5.0, 0.263, 2065.0), (5.0, 10.0, 0.478, 2911.0)),
        ((_INF, 193.0),),
        ((_INF, 69.0),),
        7920.0,
        0.35,
        7.6,
    ),
}
WIRE_NAMES: tuple[str, ...] = tuple(WIRES)

# Zimmerli's endurance data for spring steels under 10 mm (Shigley eq. 10-28): (Ssa, Ssm) MPa
ZIMMERLI_MPA = {"unpeened": (241.0, 379.0), "peened": (398.0, 534.0)}
ZIMMERLI_MAX_WIRE_MM = 10.0

# Preferred wire diameters, mm: the ISO 3 R40 preferred numbers from 0.5 to 12.5 mm (spring-wire standards such
# as EN 10270-1 list these sizes among their nominal diameters)
_R40 = (
    1.00,
    1.06,
    1.12,
    1.18,
    1.25,
    1.32,
    1.40,
    1.50,
    1.60,
    1.70,
    1.80,
    1.90,
    2.00,
    2.12,
    2.24,
    2.36,
    2.50,
    2.65,
    2.80,
    3.00,
    3.15,
    3.35,
    3.55,
    3.75,
    4.00,
    4.25,
    4.50,
    4.75,
    5.00,
    5.30,
    5.60,
    6.00,
    6.30,
    6.70,
    7.10,
    7.50,
    8.00,
    8.50,
    9.00,
    9.50,
)
PREFERRED_WIRE_MM: tuple[float, ...] = tuple(
    sorted({round(f * v, 3) for f in (0.1, 1.0, 10.0) for v in _R40 if 0.5 <= f * v <= 12.5})
)


def unknown_name(kind: str, name: str, names: Iterable[str]) -> str:
    """The message for a name not in ``names``, with the nearest one as a hint (the validation error appends the
    name given)."""
    hint = get_close_matches(name, list(names), n=1, cutoff=0.5)
    return f"unknown {kind}" + (f" (did you mean {hint[0]!r}?)" if hint else "") + f"; known: {', '.join(names)}"
