from helpers import ROOT
from zuml_studio.lang.docgen import commands_markdown


def test_committed_command_reference_is_generated_from_the_opcode_table():
    assert (ROOT / "docs" / "commands.md").read_text() == commands_markdown(), \
        "run: python -m zuml_studio.lang.docgen > docs/commands.md"
