"""The protocol's one table (zuml_studio/protocol/messages.py) and its C side: firmware/core/protocol.h is what
tools/protocol_header.py writes from the table, and no C file gives a message type, an error code or a frame's
field a value of its own (issue 36 §3)."""
import importlib.util
import re
import sys

from host_core import ROOT

from zuml_studio.protocol.messages import MESSAGE_TYPES, ErrorCode, Telemetry

spec = importlib.util.spec_from_file_location("protocol_header", ROOT / "tools" / "protocol_header.py")
generator = sys.modules.setdefault("protocol_header", importlib.util.module_from_spec(spec))
spec.loader.exec_module(generator)

SOURCES = [p for p in (ROOT / "firmware").rglob("*.[ch]") if "build" not in p.relative_to(ROOT / "firmware").parts
           and p.name != "protocol.h"]
APP = (ROOT / "firmware" / "core" / "app.c").read_text()


def test_the_committed_header_is_what_the_table_gives():
    assert generator.HEADER.read_text() == generator.header(), \
        "firmware/core/protocol.h is stale: run `.venv/bin/python tools/protocol_header.py` and commit it"
    assert generator.main(["--check"]) == 0


def test_the_header_carries_every_type_every_error_code_and_the_telemetry_frame_s_size():
    text = generator.header()
    for m in MESSAGE_TYPES:
        assert f"#define T_{m.name} 0x{m.code:02X}\n" in text
    for code in ErrorCode:
        assert f"#define E_{code.name} {code.value}\n" in text
    size = len(Telemetry(0, "charge", "", 0, 0, 0, 0, False, False, False, 0, 0, None, None, 0, 0).encode())
    assert f"#define TELEMETRY_FIXED {size}\n" in text


def test_no_c_file_defines_a_type_or_an_error_code_of_its_own_or_passes_a_bare_code():
    names = {f"T_{m.name}" for m in MESSAGE_TYPES} | {f"E_{code.name}" for code in ErrorCode}
    for path in SOURCES:
        text = path.read_text()
        own = set(re.findall(r"^\s*#define\s+([TE]_\w+)", text, re.M)) & names
        assert not own, f"{path.name} defines {own}: protocol.h holds them"
        assert not re.search(r"\bE_\w+\s*=", text), f"{path.name}: an enum of error codes; protocol.h holds them"
        assert not re.search(r"app_error\([^,]+,[^,]+,\s*\d", text), f"{path.name}: a bare error code"


def test_app_c_names_a_value_for_each_field_of_the_frames_it_writes_and_for_no_other():
    for prefix, frame in (("TM_", "TELEMETRY"), ("EV_", "EVENT")):
        fields = {name for name, _bytes in generator.fixed_fields(frame)}
        given = set(re.findall(rf"^#define {prefix}(\w+) ", APP, re.M))
        assert given == fields, frame
        assert f"{frame}_FIELDS(TX_{frame})" in APP
