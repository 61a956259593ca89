import pytest

from zuml_studio.macro_file import MacroFileError, read_macro_file, write_macro_file


@pytest.mark.parametrize("data", [b"MACRO A\nEND_MACRO\n", b"MACRO A\r\nEND_MACRO\r\n", b"\xef\xbb\xbfMACRO A\nEND_MACRO",
                                  "MACRO \u00c5\n".encode()])
def test_open_then_save_gives_the_same_bytes(tmp_path, data):
    src = tmp_path / "in.zuml"
    src.write_bytes(data)
    opened = read_macro_file(src)
    assert "\r" not in opened.text
    out = tmp_path / "out.zuml"
    write_macro_file(out, opened.text, opened)
    assert out.read_bytes() == data


@pytest.mark.parametrize("data,needle", [(b"\xff\xfe", "not UTF-8"), (b"\x2b\x09\x00\x01", "binary")])
def test_bad_files_get_a_precise_error(tmp_path, data, needle):
    src = tmp_path / "bad.zuml"
    src.write_bytes(data)
    with pytest.raises(MacroFileError, match=needle):
        read_macro_file(src)
