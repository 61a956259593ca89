import os
import threading

import pytest

from zuml_studio.file_errors import FileReadError, read_file_bytes


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
def test_a_device_is_refused_before_it_is_read(tmp_path):
    # found by benchmarks/fuzz_files.py: /dev/zero was read until the memory ran out
    with pytest.raises(FileReadError, match=r"^/dev/zero: a device, not a file$"):
        read_file_bytes("/dev/zero")


def test_a_folder_a_missing_file_and_an_empty_one(tmp_path):
    with pytest.raises(FileReadError, match="is a folder, not a file"):
        read_file_bytes(tmp_path)
    with pytest.raises(FileReadError, match="no such file"):
        read_file_bytes(tmp_path / "gone.zuml")
    (tmp_path / "empty").write_bytes(b"")
    assert read_file_bytes(tmp_path / "empty") == b""


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes (POSIX)")
def test_a_named_pipe_is_read_to_its_end(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)

    def writer():                         # a shell's <(...) in miniature
        with open(fifo, "wb") as fh:
            fh.write(b"MACRO x\n")

    thread = threading.Thread(target=writer)
    thread.start()
    try:
        assert read_file_bytes(fifo) == b"MACRO x\n"
    finally:
        thread.join()
