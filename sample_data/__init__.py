"""Bundled roughness sets (synthetic; see README.md in this folder for provenance)."""
