"""An iMAX B6's memories as the ZUML firmware leaves them, for the emulated ISP programmer
(tests/stk500_chip.py): its flash, and its EEPROM with image, staging copy, templates and calibration."""
from zuml_studio.device import messages
from zuml_studio.device.avr_install import FLASH_SIZE
from zuml_studio.device.calibration import INPUTS, Block
from zuml_studio.device.isp_store import IMAGE_SIZE, TEMPLATES_AT, TEMPLATES_FLAG_AT, TEMPLATES_READY
from zuml_studio.lang.eeprom import pack
from zuml_studio.sim.start_templates import StartTemplate, factory_templates

ZUML_FLASH = (b"\x0c\x94" * 64 + b"iMAX B6 (ZUML firmware)\0zuml-fw 0.2 imaxb6\0").ljust(FLASH_SIZE, b"\xff")


def template_bytes(number: int, template: StartTemplate) -> bytes:
    """A template as store.c keeps it: GET_TEMPLATE's 9 bytes after the number, then their XOR."""
    stored = messages.encode_response("GET_TEMPLATE", **messages.template_fields(number, template))[1:]
    check = 0
    for byte in stored:
        check ^= byte
    return stored + bytes((check,))


def b6_eeprom(records=(), templates=None) -> bytes:
    """A B6's EEPROM as the ZUML firmware leaves it: image and staging copy, templates, calibration."""
    data = bytearray(b"\xff" * 1024)
    image = pack(list(records), IMAGE_SIZE)
    data[:2 * IMAGE_SIZE] = image + image
    for number, template in (templates or factory_templates()).items():
        at = TEMPLATES_AT + (number - 1) * 10
        data[at:at + 10] = template_bytes(number, template)
    data[TEMPLATES_FLAG_AT] = TEMPLATES_READY
    data[970:] = Block(tuple((0, 30000 + k) for k in range(len(INPUTS)))).encode()
    return bytes(data)
