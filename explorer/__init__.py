"""wheelrail.explorer: the viser browser GUI (built on wheelrail.core's public API only).

Start it with ``wheelrail explore`` or :func:`wheelrail.explorer.app.serve`;
:class:`~wheelrail.explorer.app.ExplorerApp` is the server, which gives each browser tab its own
:class:`~wheelrail.explorer.browser_session.BrowserSession` (testable without a browser through a
:class:`~wheelrail.explorer.headless.HeadlessTab`).
"""
