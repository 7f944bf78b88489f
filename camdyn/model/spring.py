"""Helical compression springs: strength, rate, geometry, stability, fatigue, mass and surge (Shigley ch. 10).

Units: lengths mm, forces N, stresses MPa, rates N/mm, masses kg, frequencies Hz. Every function is plain
numpy and broadcasts, so a designer can evaluate a whole grid of candidate springs at once. Equation numbers
are those of Shigley's Mechanical Engineering Design, 10th ed.:

* spring index C = D/d (10-1); Bergstrasser factor K_B = (4C + 2)/(4C - 3) (10-5), Wahl factor
  K_W = (4C - 1)/(4C - 4) + 0.615/C (10-4); shear stress tau = K 8 F D / (pi d^3) (10-7);
* rate k = d^4 G / (8 D^3 N_a) (10-9); the end types of Table 10-1 (end coils, solid and free length);
* absolute stability L0 < (pi D / alpha) sqrt(2 (E - G) / (2 G + E)) (10-13), alpha the end-condition
  constant (Table 10-2; 0.5 between flat parallel plates);
* Sut = A / d^m (10-14, Table 10-4); static torsional yield Ssy as a fraction of Sut (Table 10-6);
* fatigue: Ssu = 0.67 Sut (10-30); Zimmerli's Ssa, Ssm (10-28) with the Gerber or Goodman line through them
  give the shear endurance Sse, and the factor of safety on the load line through the origin (Table 6-7);
* critical (surge) frequency of a spring between two flat plates f = (1/2) sqrt(k / m_a) (10-25), m_a the mass
  of the active coils, pi^2 d^2 D N_a rho / 4 (10-26).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._core.errors import InputError
from .._core.materials import WIRES, ZIMMERLI_MAX_WIRE_MM, ZIMMERLI_MPA, WireMaterial, unknown_name
from .._core.units import M_PER_MM, N_PER_M_PER_N_PER_MM

TORSIONAL_ULTIMATE_FRACTION = 0.67  # Ssu / Sut, Shigley eq. (10-30)
ALPHA_FLAT_PLATES = 0.5  # end-condition constant, both ends on flat parallel plates (Shigley Table 10-2)
# Table 10-1: end coils N_e (N_t = N_a + N_e), and the wire thicknesses the ends add to the solid and free length
_ENDS = {  # end type: (N_e, L_s = d (N_t + this), L_0 = p N_a + this many d)
    "plain": (0.0, 1.0, 1.0),
    "plain-ground": (1.0, 0.0, math.nan),  # L_0 = p (N_a + 1): see free_length
    "squared": (2.0, 1.0, 3.0),
    "squared-ground": (2.0, 0.0, 2.0),
}


def wire(name: str) -> WireMaterial:
    """The spring wire of that name (:data:`camdyn._core.materials.WIRES`)."""
    if name not in WIRES:
        raise InputError("spring.material", unknown_name("spring material", name, tuple(WIRES)) + f" (got {name!r})")
    return WIRES[name]


def _banded(bands, d):
    d = np.asarray(d, dtype=float)
    out = np.full(d.shape, bands[-1][1])
    for d_max, value in reversed(bands):
        out = np.where(d <= d_max, value, out)
    return out


def tensile_strength(material: WireMaterial, d: float | np.ndarray) -> np.ndarray:
    """Minimum tensile strength Sut = A / d^m, MPa (d mm); NaN outside the wire sizes of Table 10-4."""
    d = np.asarray(d, dtype=float)
    out = np.full(d.shape, np.nan)
    for d_min, d_max, m, A in reversed(material.bands):  # a size on a band edge takes the lower band
        out = np.where((d >= d_min) & (d <= d_max), A / d**m, out)
    return out


def shear_modulus(material: WireMaterial, d: float | np.ndarray) -> np.ndarray:
    """G, MPa (Table 10-5; music wire's depends on the size)."""
    return _banded(material.G_bands, d) * 1e3


def elastic_modulus(material: WireMaterial, d: float | np.ndarray) -> np.ndarray:
    """E, MPa (Table 10-5)."""
    return _banded(material.E_bands, d) * 1e3


def torsional_yield(material: WireMaterial, d: float | np.ndarray) -> np.ndarray:
    """Static torsional yield strength Ssy, MPa (Table 10-6, before set removal)."""
    return material.yield_fraction * tensile_strength(material, d)


def bergstrasser(C: float | np.ndarray) -> np.ndarray:
    """K_B = (4C + 2) / (4C - 3): direct shear and curvature together (eq. 10-5)."""
    C = np.asarray(C, dtype=float)
    return (4 * C + 2) / (4 * C - 3)


def wahl(C: float | np.ndarray) -> np.ndarray:
    """K_W = (4C - 1) / (4C - 4) + 0.615 / C (eq. 10-4)."""
    C = np.asarray(C, dtype=float)
    return (4 * C - 1) / (4 * C - 4) + 0.615 / C


def shear_stress(
    force: float | np.ndarray, D: float | np.ndarray, d: float | np.ndarray, factor: float | np.ndarray | None = None
) -> np.ndarray:
    """tau = K 8 F D / (pi d^3), MPa (N, mm); K the Bergstrasser factor unless given."""
    D, d = np.asarray(D, dtype=float), np.asarray(d, dtype=float)
    K = bergstrasser(D / d) if factor is None else factor
    return K * 8 * np.asarray(force, dtype=float) * D / (math.pi * d**3)


def rate(
    d: float | np.ndarray, D: float | np.ndarray, active_coils: float | np.ndarray, G: float | np.ndarray
) -> np.ndarray:
    """k = d^4 G / (8 D^3 N_a), N/mm (mm, MPa)."""
    return np.asarray(d, dtype=float) ** 4 * G / (8 * np.asarray(D, dtype=float) ** 3 * active_coils)


def _ends(end_type: str):
    if end_type not in _ENDS:
        raise InputError("spring.end_type", f"unknown end type {end_type!r}; known: {', '.join(_ENDS)}")
    return _ENDS[end_type]


def total_coils(active_coils: float | np.ndarray, end_type: str) -> np.ndarray:
    """N_t = N_a + N_e (Table 10-1)."""
    return np.asarray(active_coils, dtype=float) + _ends(end_type)[0]


def solid_length(d: float | np.ndarray, active_coils: float | np.ndarray, end_type: str) -> np.ndarray:
    """L_s: d (N_t + 1) with plain or squared ends, d N_t when ground (Table 10-1), mm."""
    return np.asarray(d, dtype=float) * (total_coils(active_coils, end_type) + _ends(end_type)[1])


def free_length(
    pitch: float | np.ndarray, d: float | np.ndarray, active_coils: float | np.ndarray, end_type: str
) -> np.ndarray:
    """L_0 from the pitch p (Table 10-1), mm."""
    p, d, na = (np.asarray(v, dtype=float) for v in (pitch, d, active_coils))
    if end_type == "plain-ground":
        return p * (na + 1)
    return p * na + _ends(end_type)[2] * d


def pitch(
    free_len: float | np.ndarray, d: float | np.ndarray, active_coils: float | np.ndarray, end_type: str
) -> np.ndarray:
    """The pitch p from the free length (the inverse of :func:`free_length`), mm."""
    L0, d, na = (np.asarray(v, dtype=float) for v in (free_len, d, active_coils))
    if end_type == "plain-ground":
        return L0 / (na + 1)
    return (L0 - _ends(end_type)[2] * d) / na


def critical_free_length(
    D: float | np.ndarray, E: float | np.ndarray, G: float | np.ndarray, alpha: float = ALPHA_FLAT_PLATES
) -> np.ndarray:
    """Longest free length that is absolutely stable against buckling, mm (eq. 10-13; 2.63 D / alpha for steel)."""
    return math.pi * np.asarray(D, dtype=float) / alpha * np.sqrt(2 * (E - G) / (2 * G + E))


def coil_mass(
    d: float | np.ndarray, D: float | np.ndarray, coils: float | np.ndarray, density_kg_m3: float
) -> np.ndarray:
    """Mass of ``coils`` turns of wire, kg: pi^2 d^2 D N rho / 4 (eq. 10-26; mm in)."""
    d, D = np.asarray(d, dtype=float) * M_PER_MM, np.asarray(D, dtype=float) * M_PER_MM
    return math.pi**2 * d**2 * D * np.asarray(coils, dtype=float) * density_kg_m3 / 4


def surge_frequency(rate_N_per_mm: float | np.ndarray, active_mass_kg: float | np.ndarray) -> np.ndarray:
    """Fundamental surge frequency of a spring between two flat plates, Hz: (1/2) sqrt(k / m_a) (eq. 10-25)."""
    return 0.5 * np.sqrt(np.asarray(rate_N_per_mm, dtype=float) * N_PER_M_PER_N_PER_MM / active_mass_kg)


# The spring as a chain of masses ([spring] model = "surge"; camdyn.model.surge, and a valvetrain's valve side)
DEFAULT_SEGMENTS = 16
DEFAULT_SURGE_DAMPING = 0.02  # damping ratio of the spring's first surge mode (steel coils: light)


def chain_segments(rate: float, spring_mass: float, segments: int, surge_damping: float) -> tuple[float, float, float]:
    """A spring of ``rate`` (SI) and mass ``spring_mass`` (kg, or its generalized mass) as ``segments`` equal lumps
    joined by springs, fixed at the far end: (each lump's mass, each segment's rate N k, each segment's damper N c_s),
    with the coils' damper c_s stiffness-proportional, set so that the first surge mode (fixed at both ends,
    w_1 = pi sqrt(k / m_s)) has the damping ratio ``surge_damping``. The lump at the moving end is half a lump."""
    n, k, m_s = segments, float(rate), float(spring_mass)
    c_s = 2.0 * surge_damping * k / (math.pi * math.sqrt(k / m_s))  # the whole spring's: zeta_1 = c_s w_1 / 2k
    return m_s / n, n * k, n * c_s


def shear_endurance(
    Ssu: float | np.ndarray,
    criterion: str = "gerber",
    peened: bool = False,
    zimmerli: tuple[float, float] | None = None,
) -> np.ndarray:
    """Sse: the shear endurance through Zimmerli's (Ssa, Ssm) on the Gerber or Goodman line to Ssu, MPa
    (``zimmerli``: other (Ssa, Ssm), MPa)."""
    Ssa, Ssm = zimmerli or ZIMMERLI_MPA["peened" if peened else "unpeened"]
    Ssu = np.asarray(Ssu, dtype=float)
    if criterion == "gerber":
        return Ssa / (1 - (Ssm / Ssu) ** 2)
    if criterion == "goodman":
        return Ssa / (1 - Ssm / Ssu)
    raise InputError("criterion", f"unknown fatigue criterion {criterion!r}; known: gerber, goodman, sines")


def fatigue_safety(
    tau_a: float | np.ndarray,
    tau_m: float | np.ndarray,
    Sut: float | np.ndarray,
    criterion: str = "gerber",
    peened: bool = False,
    zimmerli: tuple[float, float] | None = None,
) -> np.ndarray:
    """Fatigue factor of safety for infinite life on the load line through the origin (Zimmerli's data, Shigley
    Table 6-7 in shear): Gerber, Goodman, or Sines (Ssa / tau_a, the mean stress ignored). NaN where the wire
    is over 10 mm (Zimmerli's data stop there); inf where nothing alternates."""
    tau_a, tau_m = np.asarray(tau_a, dtype=float), np.asarray(tau_m, dtype=float)
    Ssu = TORSIONAL_ULTIMATE_FRACTION * np.asarray(Sut, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        if criterion == "sines":
            n = (zimmerli or ZIMMERLI_MPA["peened" if peened else "unpeened"])[0] / tau_a
        elif criterion == "goodman":
            n = 1.0 / (tau_a / shear_endurance(Ssu, "goodman", peened, zimmerli) + tau_m / Ssu)
        else:
            Sse = shear_endurance(Ssu, criterion, peened, zimmerli)
            r = 2 * tau_m * Sse / (Ssu * tau_a)
            # 0.5 (Ssu/tau_m)^2 (tau_a/Sse) (-1 + sqrt(1 + r^2)), written without the cancellation at small tau_m
            n = 2 * Sse / (tau_a * (1 + np.sqrt(1 + r**2)))
    return np.where(tau_a > 0, n, np.inf)


@dataclass(frozen=True)
class HelicalSpring:
    """A helical compression spring (mm, N/mm, MPa, kg, Hz) with the working lengths it is installed at."""

    material: str
    wire_diameter: float  # d
    mean_diameter: float  # D
    active_coils: float  # N_a
    end_type: str
    free_length: float  # L_0
    alpha: float = ALPHA_FLAT_PLATES  # end-condition constant for buckling

    @property
    def wire(self) -> WireMaterial:
        return wire(self.material)

    @property
    def outside_diameter(self) -> float:
        return self.mean_diameter + self.wire_diameter

    @property
    def inside_diameter(self) -> float:
        return self.mean_diameter - self.wire_diameter

    @property
    def index(self) -> float:
        return self.mean_diameter / self.wire_diameter

    @property
    def total_coils(self) -> float:
        return float(total_coils(self.active_coils, self.end_type))

    @property
    def solid_length(self) -> float:
        return float(solid_length(self.wire_diameter, self.active_coils, self.end_type))

    @property
    def pitch(self) -> float:
        return float(pitch(self.free_length, self.wire_diameter, self.active_coils, self.end_type))

    @property
    def shear_modulus(self) -> float:
        return float(shear_modulus(self.wire, self.wire_diameter))

    @property
    def rate(self) -> float:
        return float(rate(self.wire_diameter, self.mean_diameter, self.active_coils, self.shear_modulus))

    @property
    def strengths(self) -> tuple[float, float]:
        """(tensile strength Sut, torsional yield Ssy) of this wire size, MPa (Shigley Tables 10-4, 10-6)."""
        w, d = self.wire, self.wire_diameter
        return float(tensile_strength(w, d)), float(torsional_yield(w, d))

    def stress(self, force: float | np.ndarray) -> np.ndarray:
        """Shear stress at a force (N), MPa, with the Bergstrasser factor."""
        return shear_stress(force, self.mean_diameter, self.wire_diameter)

    def force_at(self, length: float | np.ndarray) -> np.ndarray:
        """Spring force at a length (mm), N."""
        return self.rate * (self.free_length - np.asarray(length, dtype=float))

    @property
    def solid_force(self) -> float:
        return float(self.force_at(self.solid_length))

    @property
    def critical_free_length(self) -> float:
        E = float(elastic_modulus(self.wire, self.wire_diameter))
        return float(critical_free_length(self.mean_diameter, E, self.shear_modulus, self.alpha))

    @property
    def mass(self) -> float:
        """The whole spring, end coils included, kg."""
        return float(coil_mass(self.wire_diameter, self.mean_diameter, self.total_coils, self.wire.density_kg_m3))

    @property
    def active_mass(self) -> float:
        return float(coil_mass(self.wire_diameter, self.mean_diameter, self.active_coils, self.wire.density_kg_m3))

    @property
    def surge_frequency(self) -> float:
        return float(surge_frequency(self.rate, self.active_mass))

    def fatigue_safety(
        self, force_min: float, force_max: float, criterion: str = "gerber", peened: bool = False
    ) -> float:
        """Fatigue factor of safety cycling between two forces (N); NaN over Zimmerli's 10 mm."""
        if self.wire_diameter > ZIMMERLI_MAX_WIRE_MM:
            return math.nan
        tau_a = self.stress(0.5 * (force_max - force_min))
        tau_m = self.stress(0.5 * (force_max + force_min))
        return float(fatigue_safety(tau_a, tau_m, self.strengths[0], criterion, peened))

    def json(self) -> dict:
        return {
            "material": self.material,
            "astm": self.wire.astm,
            "wire_diameter_mm": self.wire_diameter,
            "mean_diameter_mm": self.mean_diameter,
            "outside_diameter_mm": self.outside_diameter,
            "inside_diameter_mm": self.inside_diameter,
            "spring_index": self.index,
            "active_coils": self.active_coils,
            "total_coils": self.total_coils,
            "end_type": self.end_type,
            "free_length_mm": self.free_length,
            "solid_length_mm": self.solid_length,
            "pitch_mm": self.pitch,
            "rate_N_per_mm": self.rate,
            "tensile_strength_MPa": self.strengths[0],
            "torsional_yield_MPa": self.strengths[1],
            "critical_free_length_mm": self.critical_free_length,
            "mass_kg": self.mass,
            "active_mass_kg": self.active_mass,
            "surge_frequency_Hz": self.surge_frequency,
        }
