"""wheelrail.explorer: the viser browser GUI (built on wheelrail.core's public API only).

Start it with ``wheelrail explore`` or :func:`wheelrail.explorer.app.serve`;
:class:`~wheelrail.explorer.app.ExplorerApp` is the app itself (testable without a browser).
"""
