"""wheelrail.explorer: the viser browser GUI (built on wheelrail.core's public API only).

Placeholder until the explorer issue lands: `wheelrail explore` reports that it is not available yet.
"""
