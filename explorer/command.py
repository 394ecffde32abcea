"""``wheelrail explore``: the browser GUI (``wheelrail.explorer.app``), a command of the ``wheelrail`` console
script (``wheelrail.cli``), not of core."""

from __future__ import annotations

from wheelrail.core.errors import WheelrailError


def add_parser(sub):
    parser = sub.add_parser("explore", help="start the browser GUI (default http://127.0.0.1:8080)")
    parser.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1)")
    parser.add_argument("--port", type=int, default=8080, help="port (default 8080; the next free one if taken)")
    parser.add_argument(
        "--set",
        default="corrugated-rail",
        metavar="SET",
        help="bundled roughness set shown first (default corrugated-rail); upload your own in the page",
    )
    return parser


def check_address(host: str, port: int) -> None:
    """Refuse, before any server starts, a port outside 1..65535 or a host that does not resolve to an
    address of this machine (else the server thread printed a traceback and never exited, or hung)."""
    import socket

    if not 1 <= port <= 65535:
        raise WheelrailError(f"--port must be in 1..65535, got {port}")
    try:
        infos = socket.getaddrinfo(host, None, type=socket.SOCK_STREAM)
    except (OSError, UnicodeError) as error:
        raise WheelrailError(f"--host {host!r} is not an address or a known host name ({error})") from None
    family, _, _, _, address = infos[0]
    try:
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            probe.bind((address[0], 0))  # any free port: only whether the address is this machine's
    except OSError as error:
        raise WheelrailError(f"--host {host!r}: cannot listen on {address[0]} ({error.strerror})") from None


def run(args) -> int:
    check_address(args.host, args.port)
    from wheelrail.core.roughness import bundled_names
    from wheelrail.explorer.app import serve  # viser and the page: imported only when the command runs

    if args.set not in bundled_names():
        raise WheelrailError(
            f"--set {args.set!r} is not a bundled set; choose one of {', '.join(bundled_names())} "
            "(upload your own file in the page)"
        )
    return serve(host=args.host, port=args.port, roughness=args.set)
