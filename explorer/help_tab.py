"""The Help tab: the models, the contact filter, the geometry and the inputs in words."""

from __future__ import annotations

import viser

from wheelrail.core.models import REFERENCE_MODEL, model_entry
from wheelrail.core.noise.run_noise import ISO3095_DISTANCE
from wheelrail.core.parameters import ContactParameters
from wheelrail.core.roughness.analysis import DEFAULT_LINES
from wheelrail.explorer.config import COMPARE, MODEL_CHOICES
from wheelrail.explorer.panel import ResultsTab, TabParts
from wheelrail.explorer.roughness_tab import EMPTY_BAND_DB

__all__ = ["HelpTab", "help_text"]


class HelpTab(ResultsTab):
    """The models, the contact filter, the geometry and the inputs in words."""

    title, icon = "Help", viser.Icon.HELP

    def __init__(self, parts: TabParts, tab) -> None:
        super().__init__(parts, tab)
        with tab:
            self.gui.add_markdown(help_text())


def help_text() -> str:
    models = "\n".join(f"- **{m}**: {model_entry(m).label}" for m in MODEL_CHOICES[:-1])
    return (
        "**Contact models** (Pieringer, Kropp & Thompson, Wear 271, 2011):\n\n"
        + models
        + f"\n- **{COMPARE}**: every model one after another on the same configuration, {REFERENCE_MODEL} first; "
        "*Model shown* (Patch tab) chooses the one replayed and downloaded.\n\n"
        "**Contact filter**: a contact patch is several millimetres long and wide, so roughness of shorter "
        "wavelengths is partly averaged out before it excites the wheel and rail. The *contact filter* of a "
        f"model is its force level minus that of `{REFERENCE_MODEL}` (a point contact, no filtering), per "
        "third-octave band: 0 dB means no filtering, negative values show how much the patch attenuates. "
        "Dotted: reference filters for the same load, geometry and speed (CNOSSOS-EU A3 of noise mapping, and "
        "the analytic averaging and circular-patch filters). Dashed: another run overlaid on purpose.\n\n"
        "**3D view**: seen from above, x (the rolling direction) to the right, y across the rail up; grid of "
        "1 mm, bold every 5 mm. The red ellipse is the Hertz patch at the preload with its semi-axes a (along) "
        "and b (across); the colour bar marks its peak pressure p0. *Top view* / *Oblique view* set the camera.\n\n"
        "**Contact geometry**: wheel radius (rolling, along the rail), rail crown radius (across) and wheel "
        "tread radius across (empty: a cylindrical tread; negative: a concave, worn tread, which must stay "
        f"flatter than the crown), in mm; empty fields keep the paper's crossed cylinders of "
        f"{ContactParameters().radius * 1e3:g} mm (a circular "
        "patch). Otherwise the patch is an ellipse, drawn with its Hertz semi-axes.\n\n"
        "**Wheel roughness**: a bundled wheel set added to a rail set (r = r_rail + r_wheel, the wheel's lines "
        "repeating with its circumference); `none`: a smooth wheel, as in the paper. The Roughness tab then "
        "shows the rail, the wheel and their energetic sum.\n\n"
        "**Roughness spectrum**: dB re 1 µm against frequency at the speed and wavelength (top axis), averaged "
        f"over lines {DEFAULT_LINES[0]}..{DEFAULT_LINES[-1]}; dotted, for rail sets: the ISO 3095:2013 limit, put on "
        f"these bands by the CNOSSOS-EU rule. Bands more than {EMPTY_BAND_DB:g} dB below the highest hold no "
        "roughness and are not drawn.\n\n"
        "**Noise**: the run's contact force through the model track's transfer functions (rail and sleeper sound "
        "power) and, for the wheel, the effective roughness through CNOSSOS-EU's L_H,veh (the 2-DOF wheel has no "
        "radiating modes); per axle, A-weighted per band, beside the CNOSSOS-EU source on the run's own roughness "
        f"with A3. The table: L_WA per axle and the pass-by L_pAeq,Tp at {ISO3095_DISTANCE:g} m for the train set "
        "below it. "
        "*Pass-by audio* makes the pass-by of the model shown to hear and download (its calibration under the "
        "player).\n\n"
        "**Track**: the *Track* folder sets the pads, sleepers, ballast, the rail's loss factor and the pads' "
        "width (empty fields are not allowed: each shows the paper's value). A new track computes its Green's "
        "functions once (13-60 s, kept on disk); the Track tab shows its receptance and decay rate against the "
        "EN ISO 3095 limit.\n\n"
        "**Wheel**: the modal wheel (axisymmetric finite elements, n nodal diameters, the bore clamped) at the "
        "run's wheel radius: a named wheel's rim, web and hub, each dimension replaceable in the tab's *Wheel "
        "shape* folder (mm; empty: the named wheel's), and a damper's added loss factor. The tab plots its "
        "natural frequencies by family and n, its radial, axial and cross receptances at the contact beside "
        "the track's point receptance, and its sound power per band for 1 N radial force at the contact (the "
        "noise chain's modal wheel), once *Compute the wheel* is pressed (nothing is computed before, so a first "
        "Run has the machine); a new shape's modes take a few seconds, its radiation a minute or more "
        "(then kept on disk).\n\n"
        "**Run length**: at least long enough for a force spectrum at the chosen speed, at most what the "
        "roughness set holds; the page shows the range.\n\n"
        "**Each browser tab its own session**: every tab open on this explorer has its own form, runs, results "
        "and downloads (a run in one tab never changes what another shows; closing a tab stops its run). The tabs "
        "share only what is computed once for all: the tracks' Green's functions (kept on disk) and the compiled "
        "solver. *Session* saves this tab's settings to a file and loads them back, in this tab or another."
    )
