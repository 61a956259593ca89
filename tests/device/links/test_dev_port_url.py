"""Every malformed port URL gets a message that shows a valid one (issue 12, point 8)."""
import pytest

from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.links.port_url import BadPortUrl, check_port_url

BAD = {
    "socket://127.0.0.1:notaport": "the TCP port 'notaport' is not a number",
    "socket://127.0.0.1": "the TCP port is missing",
    "socket://:7777": "the host is missing",
    "socket://": "the host is missing",
    "socket://127.0.0.1:99999": "not a number from 1 to 65535",
    "socket://127.0.0.1:0": "the TCP port 0 is not from 1 to 65535",
    "socket://127.0.0.1:7777?foo": "'foo' is not an option of socket://",
    "socket://127.0.0.1:7777?logging=loud": "logging=loud: the levels are",
    "socket://127.0.0.1:7777/x": "'/x' after the port",
    "rfc2217://host:y": "the TCP port 'y'",
    "rfc2217://host:7000?timeout=soon": "timeout=soon",
    "foo://bar": "'foo://' is not a kind of port",
    "socket://[::1x]:7777": "the host in [ ] is not an IPv6 address",
    "socket://ho\x1bst:7777": "has characters no host name has",
    "  ": "the port is empty",
}


@pytest.mark.parametrize("url", sorted(BAD))
def test_a_malformed_url_says_what_is_wrong_and_what_a_valid_one_looks_like(url):
    with pytest.raises(BadPortUrl) as bad:
        check_port_url(url)
    text = str(bad.value)
    assert BAD[url] in text and "a valid one looks like socket://127.0.0.1:7777" in text


@pytest.mark.parametrize("url", ["socket://127.0.0.1:7777", "socket://[::1]:7777?logging=debug", "/dev/ttyUSB0",
                                 "COM3", "loop://", "rfc2217://host:7000?poll_modem&timeout=2"])
def test_valid_ports_pass(url):
    check_port_url(url)


def test_the_client_checks_before_pyserial():
    with pytest.raises(BadPortUrl, match="not a valid port"):
        ChargerClient("socket://127.0.0.1:notaport")
