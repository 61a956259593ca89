"""Port names and URLs checked before pyserial sees them, so a malformed one gets a message
that shows a valid one (pyserial's own answers can be as cryptic as "'debug|info|warning|error'").

Plain device names (/dev/ttyUSB0, COM3) are left to the operating system. Of pyserial's URL
handlers, ``socket://HOST:PORT`` and ``rfc2217://HOST:PORT`` are checked in full; ``loop://``,
``spy://``, ``hwgrep://`` and ``alt://`` pass through; any other scheme is refused.
"""
from __future__ import annotations

from urllib.parse import parse_qsl, urlsplit

from ..errors import DeviceLinkError
from ...i18n import N_, _

EXAMPLE = N_("socket://127.0.0.1:7777 (a `zuml virtual-charger --tcp`), /dev/ttyUSB0 or COM3")
NETWORK = {"socket": ("logging",), "rfc2217": ("logging", "ign_set_control", "poll_modem", "timeout")}
PASS_THROUGH = ("loop", "spy", "hwgrep", "alt")
LOG_LEVELS = ("debug", "info", "warning", "error")


class BadPortUrl(DeviceLinkError):
    """A port URL that cannot be right, with what a valid one looks like."""


def check_port_url(url: str) -> None:
    """Raise BadPortUrl for a malformed URL; a plain device name passes."""
    if "://" not in url:
        if not url.strip():
            _bad(url, _("the port is empty"))
        return
    scheme = url.split("://", 1)[0].lower()
    if scheme in PASS_THROUGH:
        return
    if scheme not in NETWORK:
        _bad(url, _("'{scheme}://' is not a kind of port ZUML Studio knows").format(scheme=scheme))
    try:
        parts = urlsplit(url)
    except ValueError:                  # brackets that hold no IPv6 address
        _bad(url, _("the host in [ ] is not an IPv6 address"))
    try:
        port = parts.port
    except ValueError:
        after = parts.netloc.rpartition(":")[2]
        _bad(url, _("the TCP port '{after}' is not a number from 1 to 65535").format(after=after))
    if not parts.hostname:
        _bad(url, _("the host is missing"))
    if any(not "!" <= c <= "~" for c in parts.hostname):
        _bad(url, _("the host {hostname!r} has characters no host name has").format(hostname=parts.hostname))
    if port is None:
        _bad(url, _("the TCP port is missing"))
    if not 1 <= port <= 65535:
        _bad(url, _("the TCP port {port} is not from 1 to 65535").format(port=port))
    if parts.path not in ("", "/"):
        _bad(url, _("'{path}' after the port means nothing here").format(path=parts.path))
    for key, value in parse_qsl(parts.query, keep_blank_values=True):
        allowed = NETWORK[scheme]
        if key not in allowed:
            _bad(url, _("'{key}' is not an option of {scheme}:// (options: {allowed})").format(
                    key=key, scheme=scheme, allowed=', '.join(allowed)))
        if key == "logging" and value not in LOG_LEVELS:
            _bad(url, _("logging={value}: the levels are {log_levels}").format(
                    value=value, log_levels=', '.join(LOG_LEVELS)))
        if key == "timeout" and not _number(value):
            _bad(url, _("timeout={value}: give seconds, e.g. timeout=3").format(value=value))


def _number(text: str) -> bool:
    try:
        return float(text) > 0
    except ValueError:
        return False


def _bad(url: str, why: str) -> None:
    raise BadPortUrl(_("{url}: not a valid port: {why}; a valid one looks like {example}").format(
            url=url, why=why, example=_(EXAMPLE)))
