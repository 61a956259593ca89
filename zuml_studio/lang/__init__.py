"""ZUML 2.0, the language (docs/language.md): parse (``parser``, ``grammar.lark``) to the AST (``ast``),
check (``checker``) and lint (``lint``: the safety rules), compile to the byte code of a record
(``compiler``, ``record``, ``opcodes``, ``operands``) and back (``decoder``, ``listing``), format
(``formatter``), edit from the visual editor (``visual_edits``, ``builder``), pack records into an EEPROM
image (``eeprom``), write the reference (``docgen``).

May import: ``domain`` and the top-level modules below it. Never the simulator: running byte code is
``sim``'s job, above this. No Qt."""
