"""``wheelrail cache``: list or clear the disk cache (the track's Green's functions and smaller results)."""

from __future__ import annotations

import os
import time

from wheelrail.cli.commands._common import print_json
from wheelrail.core.errors import WheelrailError


def add_parser(sub):
    parser = sub.add_parser(
        "cache",
        help="list or clear the disk cache (the Green's functions of each track computed, ~208 MB each)",
        description=(
            "List the disk cache's entries (kind, key, size, last use, what each holds), their total and the "
            "limit, or clear them. The folder is WHEELRAIL_CACHE_DIR if set, else the user's cache folder; the "
            "limit is WHEELRAIL_CACHE_MAX_GB (GB, default 4): after each new entry the least recently used "
            "ones are removed until the rest fit. Only the cache's own files are ever removed."
        ),
    )
    parser.add_argument(
        "action", nargs="?", choices=("list", "clear"), default="list", help="list (default) or clear the entries"
    )
    parser.add_argument("--kind", metavar="KIND", help="only the entries of this kind (e.g. track-wedge)")
    parser.add_argument("--json", action="store_true", help="print a machine-readable summary (SI units)")
    return parser


def _holds(entry) -> str:
    """A one-line account of what an entry holds (the track's supports for a track entry)."""
    described = (entry.meta or {}).get("description") or {}
    track = described.get("track") if isinstance(described, dict) else None
    if isinstance(track, dict) and isinstance(track.get("support"), dict):
        support = track["support"]
        try:
            return (
                f"pad {support['pad_stiffness'] / 1e6:g} MN/m, sleeper {support['sleeper_mass']:g} kg "
                f"every {support['sleeper_spacing']:g} m, ballast {support['ballast_stiffness'] / 1e6:g} MN/m, "
                f"{track.get('n_bays', '?')} bays"
            )
        except (KeyError, TypeError):
            return "a track"
    return "" if entry.meta is not None else "(no description: written by an earlier wheelrail)"


def _entries(count: int) -> str:
    return f"{count} entry" if count == 1 else f"{count} entries"


def _when(seconds: float) -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(seconds))


def _listing(folder, found, kind) -> dict:
    from wheelrail.core.files import cache

    return {
        "folder": str(folder),
        "folder_setting": "WHEELRAIL_CACHE_DIR" if os.environ.get("WHEELRAIL_CACHE_DIR") else "default",
        "limit_bytes": cache.max_bytes(),
        "total_bytes": sum(entry.size for entry in found),
        "kind": kind,
        "entries": [
            {
                "kind": entry.kind,
                "key": entry.key,
                "file": entry.path.name,
                "size_bytes": entry.size,
                "last_used": _when(entry.last_used),
                "holds": _holds(entry),
                "compute_s": (entry.meta or {}).get("compute_s"),
                "description": (entry.meta or {}).get("description"),
            }
            for entry in reversed(found)  # most recently used first
        ],
    }


def _print_listing(listing: dict) -> None:
    where = "WHEELRAIL_CACHE_DIR" if listing["folder_setting"] != "default" else "default; set WHEELRAIL_CACHE_DIR"
    print(f"cache folder: {listing['folder']} ({where})")
    print(
        f"in use: {listing['total_bytes'] / 1e9:.3f} GB in {_entries(len(listing['entries']))}"
        + (f" of kind {listing['kind']}" if listing["kind"] else "")
        + f"; limit {listing['limit_bytes'] / 1e9:g} GB (WHEELRAIL_CACHE_MAX_GB)"
    )
    if not listing["entries"]:
        return
    print(f"  {'kind':<16} {'key':<24} {'size MB':>9}  {'last used (UTC)':<20}  holds")
    for entry in listing["entries"]:
        print(
            f"  {entry['kind']:<16} {entry['key']:<24} {entry['size_bytes'] / 1e6:9.1f}  "
            f"{entry['last_used']:<20}  {entry['holds']}"
        )


def run(args) -> int:
    from wheelrail.core.files import cache

    folder = cache.cache_dir()
    if args.action == "clear":
        removed = [path for path in cache.clear(args.kind) if not path.name.startswith(".")]
        kept = [entry.path.name for entry in cache.entries() if args.kind is None or entry.kind == args.kind]
        summary = {"folder": str(folder), "kind": args.kind, "removed": [path.name for path in removed], "kept": kept}
        if args.json:
            print_json(summary)
        else:
            print(f"removed {_entries(len(removed))} from {folder}" + (f" (kind {args.kind})" if args.kind else ""))
        if kept:
            raise WheelrailError(f"{_entries(len(kept))} in {folder} could not be removed (is the folder read-only?)")
        return 0
    found = [entry for entry in cache.entries(describe=True) if args.kind is None or entry.kind == args.kind]
    listing = _listing(folder, found, args.kind)
    if args.json:
        print_json(listing)
    else:
        _print_listing(listing)
    return 0
