"""Running the explorer: uvicorn on 127.0.0.1 unless another host is explicitly allowed.

Binding another address makes the explorer reachable from other machines, which it is not
hardened for (no authentication; anyone who reaches it can start Monte Carlo runs). `serve`
therefore refuses a non-loopback host unless ``allow_remote`` is given, and then warns.
"""

from __future__ import annotations

import ipaddress
import logging
import threading
import webbrowser
from collections.abc import Callable

from sandlight.errors import ParameterError
from sandlight.web.app import LOCAL_HOSTS, create_app
from sandlight.web.limits import Limits

__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "is_loopback", "serve", "REMOTE_WARNING"]

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8765

REMOTE_WARNING = (
    "the explorer is reachable from other machines at {url}: it has no authentication, and "
    "anyone who reaches it can start Monte Carlo runs on this machine"
)


def is_loopback(host: str) -> bool:
    """Whether ``host`` names the loopback interface (127.0.0.0/8, ::1, localhost)."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def check_host(host: str, allow_remote: bool) -> str:
    """``host`` if it is loopback, or if ``allow_remote``; a `ParameterError` otherwise."""
    if not isinstance(host, str) or not host:
        raise ParameterError("--host", host, "an IP address or host name")
    if not is_loopback(host) and not allow_remote:
        raise ParameterError(
            "--host", host, "a loopback address (127.0.0.1, ::1, localhost) unless --allow-remote is given"
        )
    return host


def serve(
    host: str = DEFAULT_HOST,
    port: int = DEFAULT_PORT,
    *,
    allow_remote: bool = False,
    open_browser: bool = True,
    limits: Limits = Limits(),
    warn: Callable[[str], None] = logging.getLogger("sandlight.web").warning,
    say: Callable[[str], None] = print,
) -> None:
    """Serve the explorer until interrupted (Ctrl-C).

    Parameters
    ----------
    host : str
        Address to bind; a non-loopback one needs ``allow_remote`` (then a warning is logged).
    port : int
        TCP port, 0–65535 (0: any free port).
    open_browser : bool
        Open the page in the default browser once the server listens.
    limits : Limits
        Bounds on requests and work.
    warn, say : callable
        Where the remote-access warning and the line with the address go.
    """
    import uvicorn

    from sandlight.checks import check_whole_number

    host = check_host(host, allow_remote)
    port = check_whole_number("--port", port, 0, 65535)
    remote = not is_loopback(host)
    shown = f"[{host}]" if ":" in host else host
    url = f"http://{shown}:{port}/"
    if remote:
        warn(REMOTE_WARNING.format(url=url))
    app = create_app(limits, allowed_hosts=None if remote else LOCAL_HOSTS)
    config = uvicorn.Config(app, host=host, port=port, log_level="warning", access_log=False)
    server = uvicorn.Server(config)
    say(f"sandlight explorer at {url} (Ctrl-C stops it)")
    if open_browser:
        threading.Timer(1.0, webbrowser.open, args=(url,)).start()
    server.run()
