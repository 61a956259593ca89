"""docs/protocol.md lists every message type, field and error code of the one table; the port list."""
import re
from pathlib import Path

from zuml_studio.protocol import messages as m
from zuml_studio.device.links.ports import VIRTUAL, list_ports

DOC = (Path(__file__).resolve().parents[3] / "docs" / "protocol.md").read_text(encoding="utf-8")


def test_every_message_type_and_field_is_documented():
    for t in m.MESSAGE_TYPES:
        row = next((line for line in DOC.splitlines() if line.startswith(f"| 0x{t.code:02X} | {t.name} |")), None)
        assert row is not None, t.name
        for field in (t.request or ()) + t.response:
            assert f"`{field.name}`" in row, (t.name, field.name)


def test_every_error_code_is_documented():
    for code in m.ErrorCode:
        assert re.search(rf"^\| {code.value} \| {code.name} \|", DOC, re.M), code.name


def test_port_list_ends_with_the_virtual_charger():
    ports = list_ports()
    assert ports[-1].device == VIRTUAL and ports[-1].virtual
    assert all(not p.virtual for p in list_ports(include_virtual=False))
