"""Translation (issue 17): how the language is chosen and installed, the Russian catalogue's
completeness and correctness, and that the package hands gettext only whole, literal texts."""
import ast
import gettext
import re
import subprocess
import sys

import pytest
from babel.messages.pofile import read_po

from helpers import ROOT
from zuml_studio import i18n

PACKAGE = ROOT / "zuml_studio"
LOCALE = ROOT / "resources" / "locale"
POT = LOCALE / "zuml_studio.pot"
RU_PO = LOCALE / "ru" / "LC_MESSAGES" / "zuml_studio.po"
# {name}, {name:.2f}, {name!r}, {{ and }} (literal braces), %(name)s, %s, %d, %r
PLACEHOLDER = re.compile(r"\{\{|\}\}|\{[^{}]*\}|%\([A-Za-z_]+\)[a-z]|%[sdrif]")


@pytest.fixture
def english_afterwards():
    yield
    i18n.install("en")


def _catalogue(path):
    with path.open("rb") as fh:
        return read_po(fh)


def _messages(path):
    return [m for m in _catalogue(path) if m.id]


@pytest.mark.parametrize(("env", "preference", "expected"), [
    ({}, None, "en"),
    ({"LANG": "ru_RU.UTF-8"}, None, "ru"),
    ({"LANG": "ru_RU.UTF-8", "LC_ALL": "C"}, None, "en"),
    ({"LC_MESSAGES": "ru_RU"}, None, "ru"),
    ({"LANG": "de_DE.UTF-8"}, None, "en"),
    ({"LANG": "ru_RU.UTF-8"}, "en", "en"),
    ({}, "ru", "ru"),
    ({"ZUML_LANG": "ru", "LANG": "en_US.UTF-8"}, "en", "ru"),
    ({"ZUML_LANG": "en", "LANG": "ru_RU.UTF-8"}, None, "en"),
    ({"ZUML_LANG": "xx", "LANG": "ru_RU.UTF-8"}, None, "ru"),
])
def test_choose_language_zuml_lang_then_preference_then_locale(monkeypatch, env, preference, expected):
    for name in ("ZUML_LANG", "LC_ALL", "LC_MESSAGES", "LANG"):
        monkeypatch.delenv(name, raising=False)
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    assert i18n.choose_language(preference) == expected


def test_install_switches_the_process_language(english_afterwards):
    i18n.install("ru")
    assert i18n.current_language() == "ru"
    assert i18n._("The macro needs a name") == "Макросу нужно имя"
    i18n.install("en")
    assert i18n.current_language() == "en"
    assert i18n._("The macro needs a name") == "The macro needs a name"


def test_install_refuses_an_unknown_language():
    with pytest.raises(ValueError, match="unsupported language"):
        i18n.install("xx")


def test_a_missing_catalogue_is_a_loud_error(monkeypatch, tmp_path, english_afterwards):
    from zuml_studio.data import DataFileError
    monkeypatch.setattr(i18n, "catalogue_path", lambda language: str(tmp_path / "nowhere.mo"))
    monkeypatch.setattr(i18n, "catalogue_source_path", lambda language: str(tmp_path / "nowhere.po"))
    with pytest.raises(DataFileError, match="missing"):
        i18n.install("ru")


def test_an_editable_install_without_a_compiled_catalogue_reads_the_po(monkeypatch, tmp_path, english_afterwards):
    """`pip install -e .` runs no build step, so no .mo: the .po of the source tree is compiled in memory."""
    monkeypatch.setattr(i18n, "catalogue_path", lambda language: str(tmp_path / "nowhere.mo"))
    assert i18n.catalogue_source_path("ru") == str(RU_PO)
    i18n.install("ru")
    assert i18n._("The macro needs a name") == "Макросу нужно имя"


def test_russian_plural_forms_through_a_real_entry(english_afterwards):
    i18n.install("ru")
    forms = {n: i18n.ngettext("{n} warning", "{n} warnings", n).format(n=n) for n in (1, 2, 5, 11, 21, 22, 25)}
    assert forms == {1: "1 предупреждение", 2: "2 предупреждения", 5: "5 предупреждений",
                     11: "11 предупреждений", 21: "21 предупреждение", 22: "22 предупреждения",
                     25: "25 предупреждений"}


def test_the_russian_catalogue_has_no_untranslated_and_no_fuzzy_entry():
    untranslated, fuzzy = [], []
    for m in _messages(RU_PO):
        strings = m.string if isinstance(m.string, tuple) else (m.string,)
        if not all(strings) or (isinstance(m.id, tuple) and len(strings) != 3):
            untranslated.append(m.id)
        if m.fuzzy:
            fuzzy.append(m.id)
    assert not untranslated, f"{len(untranslated)} untranslated (./dev i18n, then translate): {untranslated[:10]}"
    assert not fuzzy, f"fuzzy entries: {fuzzy[:10]}"


def test_the_committed_pot_equals_a_fresh_extraction(tmp_path):
    fresh = tmp_path / "fresh.pot"
    proc = subprocess.run([sys.executable, "-m", "babel.messages.frontend", "extract", "-F", str(ROOT / "babel.cfg"),
                           "-k", "N_", "-k", "ngettext:1,2", "--no-location", "--sort-output", "--project",
                           "ZUML Studio", "--copyright-holder", "ZUML Studio authors", "-o", str(fresh), str(PACKAGE)],
                          cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    committed = {m.id for m in _messages(POT)}
    extracted = {m.id for m in _messages(fresh)}
    assert extracted - committed == set(), "texts not in the .pot: run ./dev i18n and translate them"
    assert committed - extracted == set(), "texts no longer in the code: run ./dev i18n"


def test_the_catalogue_covers_the_pot():
    assert {m.id for m in _messages(POT)} <= {m.id for m in _messages(RU_PO)}, "run ./dev i18n"


def test_every_translation_keeps_the_placeholders_of_its_text():
    wrong = []
    for m in _messages(RU_PO):
        ids = m.id if isinstance(m.id, tuple) else (m.id,)
        strings = m.string if isinstance(m.string, tuple) else (m.string,)
        wanted = [sorted(PLACEHOLDER.findall(i)) for i in ids]
        for s in strings:
            if s and sorted(PLACEHOLDER.findall(s)) not in wanted:
                wrong.append((m.id, s))
    assert not wrong, wrong[:5]


def test_pybabel_compiles_the_catalogue_with_its_own_checks():
    """What ./dev and CI's set-up run: a text that merely looks like a %-format (a "%" before a letter)
    is checked as one, and a translation that moves the "%" fails the whole set-up."""
    errors = [(m.id, str(err)) for m, errs in read_po(RU_PO.open("rb")).check() for err in errs]
    assert not errors, errors[:5]


def test_the_compiled_catalogue_matches_the_po():
    # ./dev compiles it before the tests; a stale .mo would show old texts.
    with open(i18n.catalogue_path("ru"), "rb") as fh:
        compiled = gettext.GNUTranslations(fh)
    for m in _messages(RU_PO):
        if isinstance(m.id, str):
            assert compiled.gettext(m.id) == m.string, m.id


# --- the code hands gettext whole literal texts ----------------------------------------------------
TRANSLATORS = {"_": 1, "N_": 1, "ngettext": 2}


def _calls(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in TRANSLATORS:
            yield node


def _literal(node) -> bool:
    return isinstance(node, ast.Constant) and isinstance(node.value, str)


def _marked_text_variable(node) -> bool:
    """A name, attribute or item holding a text marked with N_ where it was defined (a table's help
    line, an opcode's help), or looked up in such a table (``WORDS.get(key, key)``: an unknown key
    passes through untranslated): the one kind of non-literal `_` may take."""
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "get":
        return isinstance(node.func.value, (ast.Name, ast.Attribute))
    return isinstance(node, (ast.Name, ast.Attribute, ast.Subscript))


def _problems(path, root=ROOT):
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    for call in _calls(tree):
        name = call.func.id
        texts = call.args[:TRANSLATORS[name]]
        where = f"{path.relative_to(root)}:{call.lineno}"
        if len(texts) != TRANSLATORS[name] or call.keywords:
            yield f"{where}: {name}() takes its text(s) as plain positional arguments"
            continue
        for text in texts:
            if isinstance(text, ast.JoinedStr):
                yield f"{where}: an f-string in {name}(); put named placeholders in the text and .format() after"
            elif isinstance(text, ast.BinOp):
                yield f"{where}: a concatenation in {name}(); translate whole sentences"
            elif _literal(text):
                continue
            elif name == "_" and _marked_text_variable(text):
                continue
            else:
                yield f"{where}: {name}() of a computed value; mark the text with N_ where it is defined"


def _shadowing(path):
    """A function that binds ``_`` (``for _ in``, ``a, _ = ...``) and calls `_()` breaks at run time."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    for fn in ast.walk(tree):
        if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        body = [n for stmt in fn.body for n in ast.walk(stmt)]
        binds = any(isinstance(n, ast.Name) and n.id == "_" and isinstance(n.ctx, ast.Store) for n in body)
        if binds and any(isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "_" for n in body):
            yield f"{path.relative_to(ROOT)}:{fn.lineno}: {fn.name} binds _ and calls _(); name the throwaway __"


def test_no_fstring_concatenation_or_computed_value_is_translated():
    problems = [p for path in sorted(PACKAGE.rglob("*.py")) for p in _problems(path)]
    assert not problems, "\n".join(problems)


def test_no_translation_hides_inside_an_fstring():
    """pybabel does not look inside f-strings: a text written in a `_()` there never reaches the
    catalogue (a variable holding an N_-marked text may be translated there)."""
    hidden = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for fstring in (n for n in ast.walk(tree) if isinstance(n, ast.JoinedStr)):
            hidden += [f"{path.relative_to(ROOT)}:{c.lineno}" for c in _calls(fstring) if _literal(c.args[0])]
    assert not hidden, hidden


def test_no_function_shadows_the_translator():
    problems = [p for path in sorted(PACKAGE.rglob("*.py")) for p in _shadowing(path)]
    assert not problems, "\n".join(problems)


def test_the_ast_check_catches_what_it_should(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text('x = 1\n_(f"a {x}")\n_("a " + str(x))\n_(str(x))\nngettext("one", f"{x}", x)\n'
                   '_("ok {x}").format(x=x)\n_(TABLE[x])\n')
    problems = list(_problems(bad, root=tmp_path))
    assert [p.split(":")[1] for p in problems] == ["2", "3", "4", "5"], problems


def test_opcode_help_follows_the_installed_language(english_afterwards):
    """The editor's hover, completion and F1 help read ``Op.help``; the generated docs the English."""
    from zuml_studio.lang import opcodes as ops
    english = ops.CONSTANT_I.help
    i18n.install("ru")
    assert ops.CONSTANT_I.help.startswith("Держать ток") and ops.CONSTANT_I.help_text == english
    assert all(re.search("[а-я]", op.help) for op in ops.OPCODES)
