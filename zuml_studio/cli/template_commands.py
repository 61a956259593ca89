"""zuml templates list | get N | set N: the charger's start templates (START_SHABLON=n)."""
from __future__ import annotations

import argparse

from ..protocol import messages as msg
from ..domain.start_templates import TEMPLATE_COUNT, StartTemplate, TemplateError
from .common import CliError, add_force_unsafe, out, refuse_unsafe
from .device_commands import _connect, _device_errors, _with_port
from ..i18n import _


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("templates", help=_("list, read or store the charger's start templates (START_SHABLON)"))
    actions = p.add_subparsers(dest="action", required=True, metavar="ACTION")
    q = _with_port(actions.add_parser("list", help=_("every start template the charger holds")))
    q.set_defaults(run=cmd_list)
    q = _with_port(actions.add_parser("get", help=_("one start template")))
    q.add_argument("number", type=int, metavar="N")
    q.set_defaults(run=cmd_get)
    q = _with_port(actions.add_parser("set", help=_("store a start template (the values a user would enter at "
                                                    "start; one not given is left to the user)")))
    q.add_argument("number", type=int, metavar="N", help=f"1..{TEMPLATE_COUNT}")
    q.add_argument("--task", choices=msg.TASKS, default="charge")
    q.add_argument("--cycles", type=int, default=1, metavar="N", help=_("training: discharge+charge N times"))
    q.add_argument("--capacity", type=float, metavar="MAH")
    q.add_argument("--current", type=float, metavar="A")
    q.add_argument("--voltage", type=float, metavar="V", help=_("whole pack"))
    q.add_argument("--series", type=int, metavar="N")
    add_force_unsafe(q)
    q.set_defaults(run=cmd_set)


def line(number: int, template: StartTemplate) -> str:
    return f"{number:>3}  {template.describe()}"


def _number(number: int) -> int:
    if not 1 <= number <= TEMPLATE_COUNT:
        raise CliError(_("a start template is numbered 1 to {template_count}").format(template_count=TEMPLATE_COUNT))
    return number


@_device_errors
def cmd_list(args: argparse.Namespace) -> int:
    with _connect(args) as client:
        table = [(n, client.get_template(n)) for n in client.list_templates()]
    if not table:
        out(_("the charger holds no start template"))
    for number, template in table:
        out(line(number, template))
    return 0


@_device_errors
def cmd_get(args: argparse.Namespace) -> int:
    number = _number(args.number)
    with _connect(args) as client:
        out(line(number, client.get_template(number)))
    return 0


@_device_errors
def cmd_set(args: argparse.Namespace) -> int:
    number = _number(args.number)
    try:
        template = StartTemplate(args.task, args.cycles, args.capacity, args.current, args.voltage, args.series)
    except TemplateError as exc:
        raise CliError(_("start template {number}: {exc}").format(number=number, exc=exc)) from None
    with _connect(args) as client:
        refuse_unsafe(template_problems(client, number, template), args.force_unsafe,
                      _("start template {number}").format(number=number))
        stored = client.set_template(number, template)
    out(line(number, stored))
    return 0


def template_problems(client, number: int, template: StartTemplate) -> list[str]:
    """The safety check's errors for every macro on the charger that names template ``number``
    (START_SHABLON), judged with the new template: it changes what they will run with."""
    from ..lang.eeprom import ImageError, slots
    from ..safety import judge, named_template
    try:
        found = [s for s in slots(client.read_image()) if s.ok and named_template(s.record) == number]
    except ImageError:
        return []       # nothing on the charger can start from a broken record list
    passport = client.passport_if_any()
    return [_("slot {index} ({name}): ").format(index=s.index, name=s.name) + line for s in found
            for line in judge(s.record, passport, templates={number: template},
                              charger_max_a=client.info.max_charge_a).errors]
