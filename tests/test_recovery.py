import os

import pytest

from zuml_studio.recovery import RecoveryStore, atomic_write


def test_saved_text_is_offered_back_until_discarded(tmp_path):
    store = RecoveryStore(tmp_path)
    key = store.key_for("/some/macro.zuml", "1")
    store.save(key, "MACRO X\n", "/some/macro.zuml")
    (found,) = RecoveryStore(tmp_path).pending()
    assert (found.key, found.text, found.original) == (key, "MACRO X\n", "/some/macro.zuml")
    store.discard(key)
    assert store.pending() == []


def test_a_damaged_note_still_gives_the_text_back(tmp_path):
    store = RecoveryStore(tmp_path)
    store.save("abc", "MACRO Y\n", None)
    (tmp_path / "recovery" / "abc.json").write_text("{not json")
    (found,) = store.pending()
    assert found.text == "MACRO Y\n" and found.original is None


@pytest.mark.parametrize("note", [
    "[1, 2]",                                                           # was AttributeError: no .get
    '{"pid": 100000000000000000000000000000, "saved_at": 1.0}',         # was OverflowError in os.kill
    '{"pid": -1, "saved_at": 1.0}',                                     # kill(-1, 0) asks about every process
    '{"pid": true, "original": 5, "saved_at": Infinity}',
    '{"original": ["a"], "saved_at": 1e999}',
    '{"original": "", "saved_at": 100000000000000000000000000000' + "0" * 400 + '}',
])
def test_a_note_with_fields_of_the_wrong_type_reads_as_a_note_without_them(tmp_path, note):
    # findings of benchmarks/fuzz_files.py: the window's start called pending() and died
    store = RecoveryStore(tmp_path)
    store.save("abc", "MACRO Y\n", "/x.zuml")
    (tmp_path / "recovery" / "abc.json").write_text(note)
    (found,) = store.pending()
    mtime = (tmp_path / "recovery" / "abc.zuml").stat().st_mtime
    assert (found.text, found.original) == ("MACRO Y\n", None)
    assert found.saved_at in (1.0, mtime)


def test_a_window_own_text_and_a_running_instance_are_not_offered(tmp_path):
    import json
    import subprocess
    import sys
    store = RecoveryStore(tmp_path)
    store.save("mine", "t", None)
    assert store.pending(own_key="mine") == []
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        store.save("theirs", "u", None)
        note = tmp_path / "recovery" / "theirs.json"
        note.write_text(json.dumps({"original": None, "saved_at": 1.0, "pid": other.pid}))
        assert [r.key for r in store.pending(own_key="mine")] == []
    finally:
        other.kill()
        other.wait()
    assert [r.key for r in store.pending(own_key="mine")] == ["theirs"]


def test_atomic_write_replaces_whole_file(tmp_path):
    target = tmp_path / "a" / "f.bin"
    atomic_write(target, b"one")
    atomic_write(target, b"two")
    assert target.read_bytes() == b"two"
    assert [p.name for p in target.parent.iterdir()] == ["f.bin"]


def test_saved_files_are_synced_the_recovery_text_is_not(tmp_path, monkeypatch):
    # The recovery text is written after every pause in typing on the GUI thread: it guards
    # against the program crashing, which needs no fsync (docs/performance.md).
    synced = []
    monkeypatch.setattr("zuml_studio.recovery.os.fsync", synced.append)
    atomic_write(tmp_path / "saved.zuml", b"MACRO A")
    assert len(synced) == 1
    store = RecoveryStore(tmp_path)
    store.save("k", "MACRO B", None)
    assert len(synced) == 1
    assert [r.text for r in store.pending()] == ["MACRO B"]


def test_the_background_saver_writes_the_newest_text_in_order_with_discards(tmp_path):
    from zuml_studio.recovery import BackgroundSaver
    errors = []
    store = RecoveryStore(tmp_path)
    saver = BackgroundSaver(store, errors.append)
    for n in range(20):
        saver.save("k", f"MACRO A{n}", None)
    saver.wait()
    assert [r.text for r in store.pending()] == ["MACRO A19"]
    saver.save("k", "MACRO B", None)
    saver.discard("k")                      # after the write before it: nothing is left behind
    assert store.pending() == [] and errors == []
    saver.close()
    saver.save("k", "MACRO C", None)        # a save after close starts the thread again
    saver.close()
    assert [r.text for r in store.pending()] == ["MACRO C"]


def test_the_background_saver_hands_a_failure_over_and_goes_on(tmp_path):
    from zuml_studio.recovery import BackgroundSaver
    (tmp_path / "recovery").write_text("a file where the folder should be")
    errors = []

    def say(exc):
        errors.append(exc)
        raise RuntimeError("the window that would say it is gone")
    saver = BackgroundSaver(RecoveryStore(tmp_path), say)
    saver.save("k", "MACRO A", None)
    saver.wait()
    saver.save("k", "MACRO A", None)
    saver.close()
    assert len(errors) == 2 and all(isinstance(e, OSError) for e in errors)


from hypothesis import given, settings  # noqa: E402 - the property tests' own imports
from hypothesis import strategies as st  # noqa: E402 - the property tests' own imports

JSON = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
                    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(
                        st.sampled_from(["original", "saved_at", "pid"]), inner, max_size=3), max_leaves=6)


@settings(max_examples=80, deadline=None)
@given(JSON)
def test_a_note_of_any_json_still_offers_the_text(tmp_path_factory, note):
    import json
    root = tmp_path_factory.mktemp("r")
    store = RecoveryStore(root)
    store.save("k", "MACRO Z\n", None)
    (root / "recovery" / "k.json").write_text(json.dumps(note))
    found = store.pending()
    assert [f.text for f in found] in ([], ["MACRO Z\n"])       # [] only for a live process's note
    for f in found:
        assert f.original is None or isinstance(f.original, str)
        assert isinstance(f.saved_at, float) or isinstance(f.saved_at, int)


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full (a device that is always full)")
def test_atomic_write_into_a_device_writes_into_it_and_never_replaces_the_node(tmp_path):
    # found by benchmarks/fuzz_cli.py: `zuml new -o /dev/full` as root renamed a regular file over
    # /dev/full; here through a link of the test's own, so that a regression replaces only the link
    import errno
    import stat
    link = tmp_path / "full"
    link.symlink_to("/dev/full")
    with pytest.raises(OSError) as failed:
        atomic_write(link, b"MACRO x\n")
    assert failed.value.errno == errno.ENOSPC
    assert link.is_symlink() and stat.S_ISCHR(os.stat("/dev/full").st_mode)
    null = tmp_path / "null"
    null.symlink_to("/dev/null")
    atomic_write(null, b"MACRO x\n")
    assert null.is_symlink()


def test_atomic_write_through_a_link_replaces_the_file_it_names_and_keeps_the_link(tmp_path):
    real = tmp_path / "real.zuml"
    real.write_text("old")
    link = tmp_path / "link.zuml"
    link.symlink_to(real)
    atomic_write(link, b"new")
    assert link.is_symlink() and real.read_text() == "new"


def test_an_atomic_write_that_fails_leaves_the_old_file_and_no_temporary_file(tmp_path, monkeypatch):
    # issue 27: on a full disk `zuml new -o` and the virtual charger's --eeprom left .NAME.PID.tmp behind
    from zuml_studio import recovery
    target = tmp_path / "eeprom.bin"
    target.write_bytes(b"old")

    def full(fd):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(recovery.os, "fsync", full)
    with pytest.raises(OSError, match="No space left"):
        recovery.atomic_write(target, b"new" * 1000)
    assert target.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["eeprom.bin"]
    with pytest.raises(ZeroDivisionError):          # any failure while writing: the same
        with recovery.atomic_text_file(target) as fh:
            fh.write("half a row,")
            1 / 0
    assert target.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["eeprom.bin"]
