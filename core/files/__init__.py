"""What core writes to disk and reads back: atomic writes, the disk cache, run files and plain JSON values.

* :mod:`.atomic`: a file written to a temporary beside its target and renamed over it when complete;
* :mod:`.cache`: the disk cache of expensive, deterministic results (track Green's functions, wheel modes);
* :mod:`.run_file`: the digest of a saved run and the checks on a run read back from a file;
* :mod:`.jsonready`: plain JSON values from numpy-laden summaries.
"""
