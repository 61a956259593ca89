from helpers import seed_text
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.decoder import decode_record
from zuml_studio.lang.listing import format_listing, listing_rows


def test_listing_rows_cover_every_byte_once_and_carry_source_lines():
    result = compile_source(seed_text("LiPo"))
    enc = result.encoded
    rows = listing_rows(enc.record, enc.instructions, enc.nodes)
    assert b"".join(r.data for r in rows) == enc.record
    by_mnemonic = {r.mnemonic: r for r in rows}
    assert by_mnemonic["IF_V_LT"].line == 6 and by_mnemonic["IF_V_LT"].detail == "V<2.8S -> STOP_FAZE"
    assert by_mnemonic["CHECK"].detail.endswith("ok")
    end_fazes = [r.line for r in rows if r.mnemonic == "END_FAZE"]
    assert end_fazes == [7, 13, 17]
    assert [r.line for r in rows if r.mnemonic == "END_MACRO"] == [20]


def test_listing_text_of_a_decoded_record_has_no_lines_but_all_instructions():
    record = compile_source(seed_text("NiMh")).record
    decoded = decode_record(record)
    text = format_listing(listing_rows(record, decoded.instructions))
    assert "IF_DPEAK_GT" in text and "DELTA_PEAK>0.2S -> STOP_FAZE" in text
    assert text.splitlines()[0].split() == ["line", "off", "bytes", "instruction", "operands"]
