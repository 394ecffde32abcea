"""Rerun recordings of wheel/rail interaction runs: a streaming sink, whole-run export and a reader.

Why rerun: one open format (``.rrd``) that a free viewer replays with synchronised time series, images and
3D meshes on several timelines, streamable live from the loop and readable back from Python. Built on
rerun-sdk 0.41; every call used here was checked against that version (``send_columns`` with
``TimeColumn``, ``FileSink``/``GrpcSink`` in ``RecordingStream.set_sinks``, ``rerun.chunk.RrdReader`` to
read files back).

Modules, by concern: :mod:`~.schema` (entity paths, the one list of scalar series, the parameters
document, the default blueprint), :mod:`~.sink` (writing a run while it streams, or a finished one),
:mod:`~.pressure` (the contact window's images, meshes and Hertz circle), :mod:`~.outputs` (file and
viewers), :mod:`~.reader` (a file back into a ``RunResult``) and :mod:`~.cli` (command-line options).

Entity tree (mirrors the physical system; SI units, m, s, N, Pa)::

    parameters                 TextDocument (markdown + JSON): the run's header (model, line, speed, time
                               step, roughness, every model parameter), window, Hertz geometry; logged at
                               the start and again at the end (final counts)
    wheel/position             Scalars, wheel position along the rail x, m
    wheel/displacement         Scalars, xi_W, m (positive downwards)
    rail/displacement          Scalars, xi_R at the contact point, m
    roughness/under_wheel      Scalars, r under the wheel centre on the run's line, m
    roughness/equivalent       Scalars, r_eq the contact model saw (whole-run export only), m
    roughness/lines            Scalars, one series per roughness line near the run's line (heights of the
                               set given to the sink, sampled at the wheel position), m
    contact/force              Scalars, normal contact force F_n, N
    contact/length             Scalars, contact length in the rolling direction, m
    contact/area               Scalars, contact area, m² (absent for 2d; 3d: elements in contact x their
                               area, 2.3-8.5 % above Hertz's pi a b at 1 mm and 65 kN; RunResult)
    contact/pressure           DepthImage (float32, Pa, colour map 0..2 p0), 3D model only; rows = y',
                               columns = x', pixel (i, j) = element (row i, column j) of the window
    contact/pressure_surface   Mesh3D: the window raised by pressure, z = a p / p0 (the Hertz peak p0
                               rises to the Hertz radius a), coloured by pressure; x', y' in m; at every
                               ``surface_every``-th recorded map
    contact/nominal_circle     Hertz circle of radius a at the preload (5.48 mm at 65 kN), computed from the
                               contact parameters: LineStrips3D in m (files before 0.41's check: also the
                               LineStrips2D now at nominal_circle_image)
    contact/nominal_circle_image  the same circle, LineStrips2D in the pressure image's pixels
    spectra/force              BarChart, third-octave contact-force levels 50 Hz-8 kHz, dB re 1 N, abscissa
                               = band number 10 lg(f/Hz) (17 = 50 Hz, 39 = 8 kHz), bars 0.9 wide
                               (:func:`wheelrail.core.spectra.force.force_spectrum`); at the end

Timelines: ``step`` (sequence, step index), ``time`` (duration, t = step dt, stored in whole ns) and
``position_um`` (sequence, wheel position x in µm). The exact x is the ``wheel/position`` series.
"""

from wheelrail.core.recording.cli import add_recording_arguments, sink_from_args
from wheelrail.core.recording.outputs import check_recording_path
from wheelrail.core.recording.reader import read_recording
from wheelrail.core.recording.schema import APPLICATION_ID, ENTITY_PATHS, SCALAR_FIELDS, default_blueprint
from wheelrail.core.recording.sink import RecordingOptions, RecordingSink, record_result

__all__ = [
    "APPLICATION_ID",
    "ENTITY_PATHS",
    "SCALAR_FIELDS",
    "RecordingOptions",
    "RecordingSink",
    "add_recording_arguments",
    "check_recording_path",
    "default_blueprint",
    "read_recording",
    "record_result",
    "sink_from_args",
]
