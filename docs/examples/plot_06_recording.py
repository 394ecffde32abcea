"""
A run recorded with rerun and read back
=======================================

A short 3D run on the cast-iron wheel set streams every step to a rerun recording (``.rrd``): force,
displacements, roughness and the pressure map in the contact window. ``rerun run.rrd`` opens it in the
rerun viewer; here it is read back into a :class:`~wheelrail.core.engine.results.RunResult`, and the force and the
pressure map at the largest force are drawn from the file.
"""

import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from wheelrail.core.engine import prepare_run
from wheelrail.core.recording import RecordingOptions, RecordingSink, read_recording

out = Path(os.environ.get("WHEELRAIL_GALLERY_OUT", "gallery-output"))
out.mkdir(parents=True, exist_ok=True)
rrd = out / "cast-iron-wheel-3d.rrd"

run = prepare_run("cast-iron-wheel", model="3d", line=0, length=0.3)
sink = RecordingSink(rrd=str(rrd), options=RecordingOptions(record_every=1))
sink.start(run)
sink.finish(run.run(sink))  # sink(state) for every step, then the force spectrum; the file is renamed into place

back = read_recording(rrd)  # the run again, from the file
print(f"{rrd.name}: {rrd.stat().st_size / 1e6:.2f} MB, {back.force.size} steps, model {back.model}")

peak = int(np.argmax(back.force))
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.6))
left.plot(back.x, back.force / 1e3)
left.set(xlabel="x (m)", ylabel="F (kN)", title="contact force read from the recording")
extent = np.array([back.window_x[0], back.window_x[-1], back.window_y[0], back.window_y[-1]]) * 1e3
image = right.imshow(back.pressure[peak] / 1e6, origin="lower", extent=extent, cmap="magma")
right.set(xlabel="x (mm)", ylabel="y (mm)", title=f"pressure at the peak force, x = {back.x[peak]:.3f} m")
fig.colorbar(image, ax=right, label="p (MPa)")
fig.tight_layout()
