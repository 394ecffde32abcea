"""Seeded synthesis of multi-line roughness with a prescribed spectrum and lateral coherence.

The paper's measured roughness (Pieringer, Kropp & Thompson 2011, section 3.1) is not public, so the
bundled sets are synthetic imitations made here. A set is a sum of random Fourier
components on a periodic grid:

* the wavelength spectrum is prescribed as a third-octave level ``L(λ)`` in dB re 1 µm
  (:class:`SpectrumTarget`), turned into a one-sided PSD ``S(k) = 10^(L/10) (1 µm)² / (Δk(k))`` with the
  third-octave bandwidth ``Δk = k (10^(1/20) - 10^(-1/20))`` (k = 1/λ in cycles/m), so that a smooth target
  integrates back to ``L`` in each band;
* the lateral coherence is prescribed by a correlation length ``Lc(λ)`` (:class:`LateralCorrelation`):
  at each wavenumber the complex amplitudes of neighbouring lines form a Gaussian Markov chain across the
  width, ``a_m = ρ a_(m-1) + sqrt(1 - ρ²) w_m`` with ``ρ = exp(-Δy / Lc)`` and independent complex normal
  ``w_m``. Lines ``Δy n`` apart then have correlation ``ρ^n = exp(-Δy n / Lc)`` at that wavelength: a
  correlated Gaussian field in the wavenumber domain whose coherence depends on wavelength.

For equal line spectra the coherence parameter of eqs. (15)-(18) is then ``γ² = ((1/M) Σ_{m=1..M} ρ^m)²``
(:func:`expected_coherence`). Run ``python3 -m wheelrail.core.roughness.synthesis --out sample_data`` to
write the four bundled sets.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.integrate import trapezoid

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness.model import RoughnessSet
from wheelrail.core.roughness.npz_io import write_npz
from wheelrail.core.roughness.preprocessing import highpass, remove_mean
from wheelrail.core.spectra.bands import BAND_HALF_WIDTH

_UM2 = 1e-12  # m² per µm²
RELATIVE_BANDWIDTH = BAND_HALF_WIDTH - 1.0 / BAND_HALF_WIDTH  # Δk / k of a third-octave band, 0.2308


@dataclass(frozen=True, kw_only=True)
class PowerLaw:
    """Band level ``level_db + slope_db_per_decade log10(λ / wavelength)``, dB re 1 µm (λ in m)."""

    level_db: float
    wavelength: float
    slope_db_per_decade: float

    def band_power(self, wavelength: np.ndarray) -> np.ndarray:
        """Third-octave band mean square at ``wavelength`` (m), µm²."""
        return 10.0 ** ((self.level_db + self.slope_db_per_decade * np.log10(wavelength / self.wavelength)) / 10)


@dataclass(frozen=True, kw_only=True)
class Peak:
    """A peak Gaussian in log-wavelength: band power ``10^(level_db/10) exp(-u²/2)``, ``u = log10(λ/λp)/w``.

    Attributes
    ----------
    level_db : float
        Band level at the peak, dB re 1 µm.
    wavelength : float
        Peak wavelength λp, m.
    width_decades : float
        Standard deviation w of the peak in decades of wavelength.
    """

    level_db: float
    wavelength: float
    width_decades: float

    def band_power(self, wavelength: np.ndarray) -> np.ndarray:
        """Third-octave band mean square at ``wavelength`` (m), µm²."""
        u = np.log10(wavelength / self.wavelength) / self.width_decades
        return 10.0 ** (self.level_db / 10) * np.exp(-0.5 * u**2)


@dataclass(frozen=True, kw_only=True)
class SpectrumTarget:
    """Target third-octave roughness spectrum: the power sum of its components (dB re 1 µm).

    Attributes
    ----------
    components : tuple of PowerLaw or Peak
        Band powers added together.
    rolloff_wavelength : float, optional
        Below this wavelength (m) the power falls by 40 dB per decade (factor ``1 / (1 + (λr / λ)^4)``),
        as measured roughness does at wavelengths of a few mm and below (stylus size, running-in).
    """

    components: tuple = ()
    rolloff_wavelength: float | None = None

    def level_db(self, wavelength: np.ndarray) -> np.ndarray:
        """Target third-octave level at ``wavelength`` (m), dB re 1 µm."""
        wavelength = np.asarray(wavelength, dtype=float)
        power = sum(c.band_power(wavelength) for c in self.components)
        if self.rolloff_wavelength is not None:
            power = power / (1.0 + (self.rolloff_wavelength / wavelength) ** 4)
        return 10 * np.log10(power)

    def psd(self, wavenumber: np.ndarray) -> np.ndarray:
        """One-sided PSD at ``wavenumber`` k = 1/λ (cycles/m), m² per (cycle/m); 0 at k = 0."""
        k = np.asarray(wavenumber, dtype=float)
        out = np.zeros_like(k)
        positive = k > 0
        band_ms = 10 ** (self.level_db(1.0 / k[positive]) / 10) * _UM2
        out[positive] = band_ms / (RELATIVE_BANDWIDTH * k[positive])
        return out

    def band_levels(self, k_lower: np.ndarray, k_upper: np.ndarray, points: int = 400) -> np.ndarray:
        """Exact band levels of the target PSD between wavenumber edges (numerical integral), dB re 1 µm."""
        out = np.empty(len(k_lower))
        for i, (lo, hi) in enumerate(zip(k_lower, k_upper, strict=True)):
            k = np.geomspace(lo, hi, points)
            out[i] = 10 * np.log10(trapezoid(self.psd(k), k) / _UM2)
        return out


@dataclass(frozen=True, kw_only=True)
class LateralCorrelation:
    """Lateral correlation length ``Lc(λ) = clip(length (λ / wavelength)^exponent, minimum, maximum)``, m.

    Lines ``d`` apart are correlated by ``exp(-d / Lc(λ))`` at wavelength λ. A positive exponent makes long
    wavelengths coherent across the width and short ones not (paper Fig. 9, corrugated rail and cast-iron
    wheel); a small exponent and short length give low coherence throughout (sinter wheels).
    """

    length: float
    wavelength: float
    exponent: float
    minimum: float = 1e-5
    maximum: float = 10.0

    def correlation_length(self, wavelength: np.ndarray) -> np.ndarray:
        """``Lc(λ)``, m."""
        ratio = np.asarray(wavelength, dtype=float) / self.wavelength
        return np.clip(self.length * ratio**self.exponent, self.minimum, self.maximum)

    def neighbour_correlation(self, wavenumber: np.ndarray, spacing: float) -> np.ndarray:
        """ρ = exp(-spacing / Lc(1/k)) between adjacent lines ``spacing`` m apart; 1 at k = 0."""
        k = np.asarray(wavenumber, dtype=float)
        out = np.ones_like(k)
        positive = k > 0
        out[positive] = np.exp(-spacing / self.correlation_length(1.0 / k[positive]))
        return out


def expected_coherence(
    spectrum: SpectrumTarget,
    correlation: LateralCorrelation,
    spacing: float,
    k_lower: np.ndarray,
    k_upper: np.ndarray,
    half_lines: int = 3,
    points: int = 400,
) -> np.ndarray:
    """Coherence γ² of eqs. (15)-(18) that a synthesized set has in expectation (no estimation bias).

    ``S_xy(f0)`` averages ``S(k) (1/M) Σ_{m=1..M} ρ(k)^m`` over the band (lines ±m are alike), ``S_xx`` and
    ``S_yy`` average ``S(k)``, so ``γ² = (∫ S c dk / ∫ S dk)²`` with ``c = (1/M) Σ ρ^m``.
    """
    out = np.empty(len(k_lower))
    for i, (lo, hi) in enumerate(zip(k_lower, k_upper, strict=True)):
        k = np.linspace(lo, hi, points)
        s = spectrum.psd(k)
        rho = correlation.neighbour_correlation(k, spacing)
        c = np.mean([rho**m for m in range(1, half_lines + 1)], axis=0)
        out[i] = (trapezoid(s * c, k) / trapezoid(s, k)) ** 2
    return out


def synthesize(
    *,
    kind: str,
    n_lines: int,
    lateral_spacing: float,
    dx: float,
    n_samples: int,
    spectrum: SpectrumTarget,
    correlation: LateralCorrelation,
    seed: int,
    description: str = "",
    highpass_wavelength: float | None = None,
) -> RoughnessSet:
    """Synthesize a multi-line roughness set (see the module docstring for the method).

    Parameters
    ----------
    kind : {"rail", "wheel"}
        Wheel sets are one periodic circumference ``n_samples * dx`` long (the DFT synthesis is periodic).
    n_lines : int
        Number of lines, odd so that line 0 lies at y = 0; lines at ``(i - (n_lines - 1)/2) lateral_spacing``.
    lateral_spacing : float
        Δy between lines, m.
    dx : float
        Sample spacing, m.
    n_samples : int
        Samples per line.
    spectrum : SpectrumTarget
        Target third-octave level vs wavelength.
    correlation : LateralCorrelation
        Target lateral correlation length vs wavelength.
    seed : int
        Seed of ``numpy.random.default_rng``: the same seed gives the same set.
    highpass_wavelength : float, optional
        Apply :func:`wheelrail.core.roughness.highpass` at this cut-off wavelength (m) afterwards, as the
        paper's rail data was (14 cm).

    Returns
    -------
    RoughnessSet
        Zero-mean heights in m.
    """
    if n_lines < 1 or n_lines % 2 == 0:
        raise WheelrailError(f"synthesize: n_lines must be odd (line 0 at y = 0), got {n_lines}")
    if n_samples < 4:
        raise WheelrailError(f"synthesize: n_samples must be at least 4, got {n_samples}")
    rng = np.random.default_rng(seed)
    k = np.fft.rfftfreq(n_samples, d=dx)
    # E|X_j|² = S(k_j) n / (2 dx) makes the rectangular-window periodogram equal S on average.
    amplitude = np.sqrt(spectrum.psd(k) * n_samples / (2.0 * dx))
    amplitude[0] = 0.0
    if n_samples % 2 == 0:
        amplitude[-1] = 0.0  # the Nyquist bin of a real signal carries no phase; leave it out
    rho = correlation.neighbour_correlation(k, lateral_spacing)
    innovation = np.sqrt(1.0 - rho**2)

    def white() -> np.ndarray:
        return (rng.standard_normal(k.size) + 1j * rng.standard_normal(k.size)) / math.sqrt(2.0)

    spectra = np.empty((n_lines, k.size), dtype=complex)
    state = white()
    spectra[0] = state
    for line in range(1, n_lines):
        state = rho * state + innovation * white()
        spectra[line] = state
    heights = np.fft.irfft(spectra * amplitude, n=n_samples, axis=1)
    y = (np.arange(n_lines) - (n_lines - 1) / 2) * lateral_spacing
    out = RoughnessSet(heights=heights, dx=dx, y=y, kind=kind, description=description)
    if highpass_wavelength is not None:
        out = highpass(out, highpass_wavelength)
    return remove_mean(out)


# --------------------------------------------------------------------------------------------------
# The four bundled sets, imitating the paper's Figs 6, 7 and 9
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class BundledRecipe:
    """Everything needed to re-make one bundled set."""

    name: str
    kind: str
    n_lines: int
    lateral_spacing: float
    dx: float
    n_samples: int
    spectrum: SpectrumTarget
    correlation: LateralCorrelation
    seed: int
    imitates: str
    highpass_wavelength: float | None = None
    extra: dict = field(default_factory=dict)

    def make(self) -> RoughnessSet:
        """Synthesize the set."""
        description = (
            f"SYNTHETIC {self.kind} roughness '{self.name}' made by wheelrail.core.roughness.synthesis "
            f"(seed {self.seed}); imitates {self.imitates} (Pieringer, Kropp & Thompson, Wear 271, 2011)"
        )
        return synthesize(
            kind=self.kind,
            n_lines=self.n_lines,
            lateral_spacing=self.lateral_spacing,
            dx=self.dx,
            n_samples=self.n_samples,
            spectrum=self.spectrum,
            correlation=self.correlation,
            seed=self.seed,
            description=description,
            highpass_wavelength=self.highpass_wavelength,
        )


BUNDLED_RECIPES = (
    BundledRecipe(
        name="corrugated-rail",
        kind="rail",
        n_lines=19,
        lateral_spacing=1e-3,
        dx=1e-3,
        n_samples=8000,
        spectrum=SpectrumTarget(
            components=(
                PowerLaw(level_db=-2.0, wavelength=0.1, slope_db_per_decade=12.0),
                Peak(level_db=18.0, wavelength=0.0556, width_decades=0.04),
            ),
            rolloff_wavelength=2.5e-3,
        ),
        correlation=LateralCorrelation(length=4e-3, wavelength=0.018, exponent=4.0, minimum=2e-4),
        seed=20110301,
        highpass_wavelength=0.14,
        imitates=(
            "the CAT measurement of a corrugated Stockholm metro rail: 19 lines 1 mm apart, dx 1 mm, 8 m, "
            "corrugation of 55.6 mm wavelength (500 Hz band at 100 km/h), laterally coherent up to ~1 kHz, "
            "incoherent above 2 kHz, high-passed at 14 cm"
        ),
    ),
    BundledRecipe(
        name="cast-iron-wheel",
        kind="wheel",
        n_lines=25,
        lateral_spacing=2e-3,
        dx=0.5e-3,
        n_samples=5800,
        spectrum=SpectrumTarget(
            components=(
                PowerLaw(level_db=-6.0, wavelength=0.1, slope_db_per_decade=6.0),
                Peak(level_db=8.0, wavelength=0.09, width_decades=0.15),
            ),
            rolloff_wavelength=2.5e-3,
        ),
        correlation=LateralCorrelation(length=8e-3, wavelength=0.018, exponent=3.0),
        seed=20110302,
        imitates=(
            "the wheel with cast-iron block brakes: 25 lines 2 mm apart, dx 0.5 mm, 2.9 m circumference, "
            "broad peak near 90 mm (~300 Hz at 100 km/h), fairly coherent below 1 kHz, low above 2 kHz"
        ),
    ),
    BundledRecipe(
        name="sinter-wheel-1",
        kind="wheel",
        n_lines=25,
        lateral_spacing=2e-3,
        dx=0.5e-3,
        n_samples=5800,
        spectrum=SpectrumTarget(
            components=(
                PowerLaw(level_db=-9.0, wavelength=0.1, slope_db_per_decade=4.0),
                PowerLaw(level_db=-12.0, wavelength=0.005, slope_db_per_decade=-15.0),
            ),
            rolloff_wavelength=2.5e-3,
        ),
        correlation=LateralCorrelation(length=1.5e-3, wavelength=0.018, exponent=0.5, maximum=3e-3),
        seed=20110303,
        imitates=(
            "wheel 1 with sinter block brakes: same grid as the cast-iron wheel, much lower roughness "
            "except at short wavelengths (high frequencies), low lateral coherence throughout"
        ),
    ),
    BundledRecipe(
        name="sinter-wheel-2",
        kind="wheel",
        n_lines=25,
        lateral_spacing=2e-3,
        dx=0.5e-3,
        n_samples=5800,
        spectrum=SpectrumTarget(
            components=(
                PowerLaw(level_db=-8.0, wavelength=0.1, slope_db_per_decade=3.0),
                PowerLaw(level_db=-11.0, wavelength=0.004, slope_db_per_decade=-14.0),
            ),
            rolloff_wavelength=2.5e-3,
        ),
        correlation=LateralCorrelation(length=1.2e-3, wavelength=0.018, exponent=0.3, maximum=2.5e-3),
        seed=20110304,
        imitates=("wheel 2 with sinter block brakes: like wheel 1 with a slightly different spectrum and another seed"),
    ),
)


def write_bundled_sets(folder: str | Path) -> list[Path]:
    """Write the four bundled sets as float32 NPZ files into ``folder`` (normally ``sample_data``)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise WheelrailError(f"{folder}: output folder does not exist")
    paths = []
    for recipe in BUNDLED_RECIPES:
        paths.append(write_npz(recipe.make(), folder / f"{recipe.name}.npz", dtype=np.float32))
    return paths


def main(argv: list[str] | None = None) -> int:
    """``python3 -m wheelrail.core.roughness.synthesis --out sample_data``: (re)make the bundled sets."""
    parser = argparse.ArgumentParser(description="Write the bundled synthetic roughness sets (NPZ).")
    parser.add_argument("--out", required=True, help="output folder, normally sample_data")
    args = parser.parse_args(argv)
    try:
        for path in write_bundled_sets(args.out):
            print(f"{path}  {path.stat().st_size / 1e6:.2f} MB")
    except WheelrailError as error:
        print(f"wheelrail.core.roughness.synthesis: error: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
