"""What every front end draws with, so that the recording, the explorer and the figures look alike (numpy only).

* :mod:`.palette`: the figures' colours, one per contact model and per noise component, drawn together;
* :mod:`.patch`: the contact patch's pressure colour ramp, the triangles of a window of elements and the Hertz
  circle.
"""
