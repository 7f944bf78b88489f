"""Spring surge against the cam's harmonics.

A helical spring between two plates resonates at its surge frequency f_s (and its multiples). The cam drives
the spring's end with the lift, whose Fourier series over a revolution has harmonics at j times the cam
frequency. A surge frequency on a strong harmonic makes the coils resonate: the spring force then departs from
k x + F0, and the follower may jump early. Shigley (Mechanical Engineering Design, section 10-9) asks for a
critical frequency 15 to 20 times the frequency of the motion; that rule and the harmonic next to f_s are
judged here.

``size --buildable`` (and the spring ``check`` weighs, where one exists) keeps the surge frequency clear of the
strong harmonics at every speed up to the top one (:func:`surge_floor_hz`): above the highest strong harmonic
(lift amplitude >= 1 % of the largest) by a quarter of the harmonic spacing at the top speed. At a lower speed
every harmonic moves down, so no strong one comes within a quarter spacing of f_s at any speed in [0, top].
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .._core.units import FFT_GRID

if TYPE_CHECKING:
    from ..model.motion import Motion

SURGE_MIN_RATIO = 15.0  # f_s / f_cam below this draws a warning (Shigley: 15 to 20)
STRONG_HARMONIC = 0.01  # a harmonic whose lift amplitude is at least this fraction of the largest one is strong
ON_HARMONIC = 0.25  # f_s within this fraction of the harmonic spacing (the cam frequency) sits on a harmonic


@dataclass(frozen=True)
class CamHarmonics:
    """The lift's Fourier amplitudes per harmonic j = 0, 1, ... (the motion's unit) at a cam speed (rpm)."""

    speed_rpm: float
    amplitudes: np.ndarray

    @property
    def cam_frequency(self) -> float:
        """Hz: one revolution per cycle."""
        return self.speed_rpm / 60.0

    def relative(self, j: int) -> float:
        """Amplitude of harmonic j over the largest (j >= 1)."""
        a = self.amplitudes
        return float(a[j] / np.max(a[1:])) if 0 < j < a.size else 0.0


def cam_harmonics(motion: Motion, speed_rpm: float, n: int = FFT_GRID) -> CamHarmonics:
    """The lift's harmonic amplitudes: |c_j| of s(theta) = sum c_j e^(i j theta), doubled for j >= 1."""
    s = motion.sample(n)[1][0]
    a = np.abs(np.fft.rfft(s)) * (2.0 / n)
    a[0] *= 0.5
    return CamHarmonics(float(speed_rpm), a)


@dataclass(frozen=True)
class SurgeReport:
    """The surge frequency against the harmonics around it."""

    frequency: float  # Hz
    cam_frequency: float  # Hz
    near: tuple[tuple[int, float, float], ...]  # (harmonic j, its frequency Hz, relative amplitude) either side
    warnings: tuple[str, ...] = field(default=())

    @property
    def ratio(self) -> float:
        return self.frequency / self.cam_frequency

    def json(self) -> dict:
        return {
            "surge_frequency_Hz": self.frequency,
            "cam_frequency_Hz": self.cam_frequency,
            "surge_to_cam_frequency_ratio": self.ratio,
            "harmonics_near": [{"harmonic": j, "frequency_Hz": f, "relative_amplitude": a} for j, f, a in self.near],
        }


def surge_floor_hz(harmonics: CamHarmonics, top_speed_rpm: float) -> float:
    """The least surge frequency (Hz) clear of the cam's strong harmonics at every speed up to ``top_speed_rpm``:
    ``(J + 1/4) * top / 60``, J the highest harmonic whose lift amplitude is at least 1 % of the largest."""
    rel = harmonics.amplitudes[1:] / np.max(harmonics.amplitudes[1:])
    strong = np.nonzero(rel >= STRONG_HARMONIC)[0]
    top_j = int(strong[-1]) + 1 if strong.size else 1
    return (top_j + ON_HARMONIC) * top_speed_rpm / 60.0


def judge_surge(surge_hz: float, harmonics: CamHarmonics) -> SurgeReport:
    """The harmonics either side of the surge frequency, and a warning for each way it can resonate."""
    fc = harmonics.cam_frequency
    r = surge_hz / fc
    lo = max(1, int(np.floor(r)))
    near = tuple((j, j * fc, harmonics.relative(j)) for j in (lo, lo + 1) if j < harmonics.amplitudes.size)
    warnings = []
    if r < SURGE_MIN_RATIO:
        warnings.append(
            f"spring surge at {surge_hz:.4g} Hz is only {r:.3g} times the cam frequency ({fc:.4g} Hz at "
            f"{harmonics.speed_rpm:g} rpm): Shigley asks for 15 to 20"
        )
    j = max(1, int(round(r)))
    rel = harmonics.relative(j)
    if abs(r - j) <= ON_HARMONIC and rel >= STRONG_HARMONIC:
        warnings.append(
            f"spring surge at {surge_hz:.4g} Hz sits on cam harmonic {j} ({j * fc:.4g} Hz at "
            f"{harmonics.speed_rpm:g} rpm), whose lift amplitude is {100 * rel:.3g} % of the largest: the coils "
            "will resonate (stiffen the spring or lighten its coils)"
        )
    return SurgeReport(float(surge_hz), fc, near, tuple(warnings))
