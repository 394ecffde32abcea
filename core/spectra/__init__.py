"""Spectra and levels: third-octave bands, spectra of sampled signals, the contact force's spectrum, levels in dB.

The modules, each imported by its path (the package imports none of them, so each stays cheap to load):

* :mod:`.bands`: the exact base-10 third-octave bands, their nominal names, the band ranges of the outputs,
  wavelength and frequency bands (:class:`~wheelrail.core.spectra.bands.Bands`) and the mapping of levels
  between them;
* :mod:`.narrowband`: the Hann-windowed narrowband spectrum of a signal, band powers and levels, block spectra and
  the band coherence;
* :mod:`.record`: the record a band spectrum analyses and which bands it resolves;
* :mod:`.force`: the contact force's band spectrum and its record;
* :mod:`.levels`: level references, A-weighting, energetic sums, the mean over lines, differences and the contact
  filter.
"""
