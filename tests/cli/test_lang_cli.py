"""The zuml CLI as users and checks run it: output format, exit codes, no tracebacks."""
import pytest

from helpers import MACROS, seed_text
from tests_cli_util import run_zuml


def test_check_prints_file_line_col_severity_message_code(tmp_path):
    bad = tmp_path / "bad.zuml"
    bad.write_text(seed_text("LiPo").replace("CONSTANT_I=1C", "CONSTANT_I=1"))
    rc, out, err = run_zuml("check", "--no-hints", str(bad), str(MACROS / "NiMh.zuml"))
    assert rc == 1
    assert out.splitlines()[0] == f"{bad}:5:16: error: CONSTANT_I needs a unit: 2A or 0.5C [E201]"


def test_check_of_the_seed_macros_exits_zero():
    rc, out, err = run_zuml("check", *[str(p) for p in sorted(MACROS.glob("*.zuml"))])
    assert rc == 0, out + err
    assert "error" not in out


def test_compile_hex_listing_and_output(tmp_path):
    rc, out, _ = run_zuml("compile", str(MACROS / "LiPo.zuml"), "--hex")
    assert rc == 0
    assert out.strip().startswith("2b 09 16 27 4c 69 50 6f 00") and out.strip().endswith("02 02 5b")
    target = tmp_path / "lipo.bin"
    rc, out, _ = run_zuml("compile", str(MACROS / "LiPo.zuml"), "-o", str(target), "--listing")
    assert rc == 0 and "IF_I_LT" in out
    assert target.read_bytes().hex(" ") == run_zuml("compile", str(MACROS / "LiPo.zuml"), "--hex")[1].strip()


def test_decompile_prints_canonical_text(tmp_path):
    target = tmp_path / "nimh.bin"
    run_zuml("compile", str(MACROS / "NiMh.zuml"), "-o", str(target))
    rc, out, _ = run_zuml("decompile", str(target))
    assert rc == 0
    assert "IF(DELTA_PEAK>0.2S) STOP_FAZE" in out and out.startswith("MACRO NiMh\n")


def test_image_pack_and_list(tmp_path):
    image = tmp_path / "eeprom.bin"
    rc, out, _ = run_zuml("image", *[str(MACROS / f"{n}.zuml") for n in ("Pb", "LiPo")], "-o", str(image),
                          "--size", "512")
    assert rc == 0 and image.stat().st_size == 512
    rc, out, _ = run_zuml("image", "--list", str(image))
    assert rc == 0
    lines = out.splitlines()
    assert lines[1].split()[3:] == ["Pb", "Pb", "ok"] and lines[2].split()[3:] == ["LiPo", "LiPo", "ok"]

    lipo = tmp_path / "lipo.bin"
    rc, out, _ = run_zuml("image", "--extract", "1", str(image), "-o", str(lipo))
    assert rc == 0 and out == f"{lipo}: slot 1 (LiPo), 43 bytes\n"
    _, compiled, _ = run_zuml("compile", str(MACROS / "LiPo.zuml"), "--hex")
    assert lipo.read_bytes().hex(" ") == compiled.strip()
    rc, _, err = run_zuml("image", "--extract", "2", str(image), "-o", str(lipo))
    assert rc == 1 and err.strip().endswith("there is no slot 2; the image has 2")


@pytest.mark.parametrize("args,needle", [
    (("compile", "/nonexistent.zuml"), "no such file"),
    (("decompile", "__BIN__"), "not a valid ZUML record"),
    (("check", "__BINARY_TEXT__"), "not UTF-8"),
    (("image", "--list", "__BIN__"), "past the end of memory"),
])
def test_errors_are_one_line_and_never_a_traceback(tmp_path, args, needle):
    junk = tmp_path / "junk.bin"
    junk.write_bytes(bytes([0x30, 1, 2, 3, 0xFF, 0xFE]))
    args = [str(junk) if a in ("__BIN__", "__BINARY_TEXT__") else a for a in args]
    rc, out, err = run_zuml(*args)
    assert rc != 0
    assert "Traceback" not in err
    assert needle in err or needle in out


def test_new_writes_a_clean_macro(tmp_path):
    target = tmp_path / "pack.zuml"
    rc, out, err = run_zuml("new", "--chemistry", "nimh", "--series", "4", "--capacity", "2000", "-o", str(target))
    assert rc == 0 and err == "" and "NiMh-4S-2000" in out
    rc, out, _ = run_zuml("check", str(target))
    assert rc == 0 and out == ""


def test_new_refuses_bad_answers_in_one_line():
    rc, _, err = run_zuml("new", "--chemistry", "NiMh", "--series", "4", "--capacity", "2000", "--rate", "0.25C")
    assert rc == 2 and "no reliable -dV" in err and "Traceback" not in err


@pytest.mark.parametrize("args,needle", [
    (("decompile", "__TEXT__"), "a macro's text, not a compiled record: `zuml compile __TEXT__` makes one"),
    (("image", "--list", "__TEXT__"), "a macro's text, not an EEPROM image: `zuml image __TEXT__ -o eeprom.bin`"),
    (("image", "--extract", "0", "__TEXT__", "-o", "x.bin"), "a macro's text, not an EEPROM image"),
    (("compile", "__RECORD__"), "not UTF-8 text (byte 0x80 at offset 15): a compiled record? "
                                "`zuml decompile __RECORD__` prints its text"),
    (("check", "__RECORD__.rec"), "a macro is UTF-8 text; a compiled record is read from a file named .bin"),
])
def test_a_text_where_bytes_belong_and_bytes_where_text_belongs_say_what_to_run(zuml, tmp_path, args, needle):
    text = tmp_path / "pack.zuml"
    text.write_text("// my pack\n" + seed_text("NiMh"))
    record = tmp_path / "pack.bin"
    assert zuml("compile", str(text), "-o", str(record))[0] == 0
    (tmp_path / "pack.bin.rec").write_bytes(record.read_bytes())
    swap = {"__TEXT__": str(text), "__RECORD__": str(record)}
    args = [swap.get(a, a).replace("__RECORD__", str(record)) for a in args]
    rc, _, err = zuml(*args)
    assert rc in (1, 2) and err.count("\n") == 1
    for key, value in swap.items():
        needle = needle.replace(key, value)
    assert needle in err
