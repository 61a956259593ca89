"""The one wording of any error, for the window (a sentence) and the command line (the message's case);
the device errors' own words are held by tests/ui/device/test_device_errors.py and tests/cli."""
from zuml_studio.device.errors import DeviceError, Disconnected
from zuml_studio.error_words import describe_error
from zuml_studio.lang.eeprom import ImageError
from zuml_studio.packs.register import PackError


def test_a_package_error_is_its_message_a_sentence_in_the_window():
    assert describe_error(PackError("pack 'A1': no such pack")) == "Pack 'A1': no such pack"
    assert describe_error(PackError("pack 'A1': no such pack"), sentence=False) == "pack 'A1': no such pack"


def test_the_command_line_keeps_the_case_the_window_capitalises():
    refused = DeviceError(3, "CAL_READ: not a request this firmware knows")
    assert describe_error(refused, sentence=False) == "the charger refused: CAL_READ: not a request this firmware knows"
    assert describe_error(refused, "stop") == "The charger refused: CAL_READ: not a request this firmware knows"
    assert describe_error(ImageError(4, "bad length"), sentence=False) == "EEPROM image: offset 4: bad length"
    assert describe_error(Disconnected("/dev/ttyUSB0: closed"), "link") == "Disconnected: /dev/ttyUSB0: closed"


def test_foreign_errors():
    missing = FileNotFoundError(2, "No such file or directory", "/tmp/x.zuml")
    assert describe_error(missing) == "/tmp/x.zuml No such file or directory"
    assert describe_error(missing, "connect") == "Cannot connect: No such file or directory"
    assert describe_error(ValueError("speed must be 1 to 1000"), "connect") == (
        "Cannot start the virtual charger: speed must be 1 to 1000")
    assert describe_error(ValueError("bad number")) == "Bad number"
    assert describe_error(KeyError("x")) == "Internal error: KeyError: 'x'"
