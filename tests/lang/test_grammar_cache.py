"""The analysed grammar is cached in the user's cache directory (never the package's), and a
cache that cannot be written or read is no reason to fail."""
import os
import subprocess
import sys

CHECK = ("from zuml_studio.lang.compiler import compile_source\n"
         "r = compile_source('MACRO A\\n AKK_TYPE=LiPo\\n CHARGE_SECTION\\n FAZE\\n CONSTANT_I=1A\\n"
         " IF(V>4.2S) STOP_FAZE\\n END_FAZE\\n END_SECTION\\nEND_MACRO\\n')\n"
         "print(r.ok, len(r.record))")


def _check(cache_dir) -> str:
    env = os.environ | {"ZUML_STUDIO_CACHE_DIR": str(cache_dir)}
    return subprocess.run([sys.executable, "-c", CHECK], env=env, capture_output=True, text=True,
                          check=True).stdout


def test_the_grammar_is_cached_and_the_cached_one_parses_the_same(tmp_path):
    first = _check(tmp_path)
    assert (tmp_path / "grammar.lark-cache").stat().st_size > 0
    assert _check(tmp_path) == first and first.startswith("True")


def test_a_cache_directory_that_cannot_be_made_or_a_broken_cache_file_is_ignored(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a directory")
    assert _check(blocker / "sub").startswith("True")
    (tmp_path / "grammar.lark-cache").write_bytes(b"garbage\n\x80\x04junk")
    assert _check(tmp_path).startswith("True")
