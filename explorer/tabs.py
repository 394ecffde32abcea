"""The results panel's tabs in page order (:data:`RESULT_TABS`): another tab is one more class (a
:class:`~wheelrail.explorer.panel.ResultsTab` in its own module) and one more entry here."""

from __future__ import annotations

from wheelrail.explorer.help_tab import HelpTab
from wheelrail.explorer.noise_tab import NoiseTab
from wheelrail.explorer.patch_tab import PatchTab
from wheelrail.explorer.roughness_tab import RoughnessTab
from wheelrail.explorer.spectra_tab import SpectraTab
from wheelrail.explorer.track_tab import TrackTab
from wheelrail.explorer.wheel_tab import WheelTab

__all__ = ["RESULT_TABS", "HelpTab", "NoiseTab", "PatchTab", "RoughnessTab", "SpectraTab", "TrackTab", "WheelTab"]

RESULT_TABS = (PatchTab, SpectraTab, NoiseTab, TrackTab, WheelTab, RoughnessTab, HelpTab)
