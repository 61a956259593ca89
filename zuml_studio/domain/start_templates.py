"""The charger's start templates (START_SHABLON=n, code 20): stored sets of the values a user would
otherwise enter at start (task, repetitions, capacity, current, voltage, cells).

A charger holds at most ``TEMPLATE_COUNT`` templates, numbered 1..16. The factory table is
``data/start_templates.toml``; the virtual charger starts with it and changes it over the
protocol, the simulator uses it as its charger's table.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from typing import Mapping

from .. import data
from ..data import DataFileError
from ..errors import ZumlError
from ..i18n import _, ngettext
from .tasks import TASK_WORDS, TASKS

TEMPLATE_COUNT = 16
TEMPLATES_FILE = "start_templates.toml"


class TemplateError(ZumlError, ValueError):
    """A template that cannot be stored (a value out of range, an unknown task)."""


@dataclass(frozen=True)
class StartTemplate:
    task: str = "charge"
    repetitions: int = 1
    capacity_mah: float | None = None      # None: not in the template (the value entered at start stands)
    current_a: float | None = None
    voltage_v: float | None = None
    series: int | None = None

    def __post_init__(self) -> None:
        if self.task not in TASKS:
            raise TemplateError(_("task must be one of {tasks}, not {task!r}").format(
                    tasks=', '.join(TASKS), task=self.task))
        if not 1 <= self.repetitions <= 255:
            raise TemplateError(_("repetitions must be 1..255"))
        if self.capacity_mah is not None and not 1 < self.capacity_mah < 65535:
            raise TemplateError(_("capacity must be 2..65534 mAh"))
        for name in ("current_a", "voltage_v"):
            value = getattr(self, name)
            if value is not None and not 0 < value <= 65.535:
                raise TemplateError(_("{split} must be above 0 and at most 65.535").format(split=name.split('_')[0]))
        if self.series is not None and not 1 <= self.series <= 255:
            raise TemplateError(_("cells must be 1..255"))

    def describe(self) -> str:
        """The template in a line of the installed language (the numbers and units as they are)."""
        parts = [_(TASK_WORDS[self.task]) + (f" x{self.repetitions}" if self.task == "train" else "")]
        if self.capacity_mah:
            parts.append(f"{self.capacity_mah:g} mAh")
        if self.current_a:
            parts.append(f"{self.current_a:g} A")
        if self.voltage_v:
            parts.append(f"{self.voltage_v:g} V")
        if self.series:
            parts.append(ngettext("{n} cell", "{n} cells", self.series).format(n=self.series))
        return ", ".join(parts)


def check_number(number: int) -> int:
    if not 1 <= number <= TEMPLATE_COUNT:
        raise TemplateError(_("a start template is numbered 1..{template_count}, not {number}").format(
                template_count=TEMPLATE_COUNT, number=number))
    return number


@functools.cache
def factory_templates() -> Mapping[int, StartTemplate]:
    """The factory table; a missing or broken file is a loud error."""
    where = data.location(TEMPLATES_FILE)
    table: dict[int, StartTemplate] = {}
    try:
        for entry in data.read_toml(TEMPLATES_FILE)["template"]:
            entry = dict(entry)
            number = check_number(int(entry.pop("number")))
            try:
                table[number] = StartTemplate(**entry)
            except (TypeError, TemplateError) as exc:
                raise DataFileError(_("data file {where}: template {number}: {exc}").format(
                        where=where, number=number, exc=exc)) from None
    except (KeyError, TypeError, ValueError) as exc:
        raise DataFileError(_("data file {where}: {exc}").format(where=where, exc=exc)) from None
    return table


def chosen_template(declared: int | None, chosen_at_start: int | None) -> int | None:
    """The template a start uses: the macro's START_SHABLON wins over the one chosen at start."""
    return declared if declared is not None else chosen_at_start


def apply_template(params, template: StartTemplate):
    """``params`` (a StartParams) with the template's values in place of those entered; a value the
    template leaves out keeps the one entered."""
    return replace(params, task=template.task, repetitions=template.repetitions,
                   capacity_mah=template.capacity_mah or params.capacity_mah,
                   current_a=template.current_a or params.current_a,
                   voltage_v=template.voltage_v or params.voltage_v,
                   series=template.series or params.series)
