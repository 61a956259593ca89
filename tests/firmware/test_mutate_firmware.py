"""tools/mutate_firmware.py's mutants: found by tokenizing the C (never in comments, strings or #include lines),
one change each, and the same set whatever lines the code has moved to. The runner itself is slow and runs by
hand (docs/firmware.md, *Mutation testing*)."""
import importlib.util
import sys

from host_core import FIRMWARE, ROOT

spec = importlib.util.spec_from_file_location("mutate_firmware", ROOT / "tools" / "mutate_firmware.py")
mutate = sys.modules.setdefault("mutate_firmware", importlib.util.module_from_spec(spec))
spec.loader.exec_module(mutate)

SOURCE = """#include <stdint.h>
#define TRIP_X_MV 500       /* a threshold: x2, /2, +-1 */
#define FAST 4
#define TEXT "a > b"
static const char *s = "x < y";   // a > b in a comment
/* if (a >= b) in a comment */
static int f(const int *p, int a)
{
    static const int t[4] = {7, 1};
    if (p->x >= a << 2)
        stage_off();
    return a != 3 && t[2] && _BV(5);
}
"""


def test_each_comparison_limit_and_switch_off_is_one_mutant_and_nothing_in_text_is():
    got = {(m.line, m.function, m.kind, m.original, m.replacement) for m in mutate.mutants_of("protect.c", SOURCE)}
    assert got == {
        (2, "#define TRIP_X_MV", "constant", "500", r) for r in ("((500) * 2)", "((500) / 2)", "(500 + 1)", "(500 - 1)")
    } | {
        (3, "#define FAST", "constant", "4", "((4) * 2)"), (3, "#define FAST", "constant", "4", "((4) / 2)"),
        (9, "f", "literal", "7", "(7 * 2)"), (9, "f", "literal", "7", "(7 / 2)"),
        (10, "f", "compare", ">=", ">"), (10, "f", "compare", ">=", "<"),
        (10, "f", "guard", "(p->x >= a << 2)", "(0 && (p->x >= a << 2))"),
        (11, "f", "call", "stage_off()", "(void)0"),
        (12, "f", "compare", "!=", "=="), (12, "f", "literal", "3", "(3 * 2)"), (12, "f", "literal", "3", "(3 / 2)"),
    }


def test_a_mutant_changes_only_its_span():
    m = next(m for m in mutate.mutants_of("stage.c", SOURCE) if m.kind == "call")
    assert m.apply(SOURCE) == SOURCE.replace("        stage_off();", "        (void)0;")


def test_board_c_is_mutated_in_its_limits_only():
    text = "#define CAPACITY_LIMIT 10\n#define UBRR 34\nvoid slow_limits(void) { if (a > b) x(); }\n" \
           "void hal_uart_write(void) { if (a > b) x(); }\n"
    assert {(m.function, m.kind) for m in mutate.mutants_of("board.c", text)} == {
        ("#define CAPACITY_LIMIT", "constant"), ("slow_limits", "compare"), ("slow_limits", "guard")}


def test_the_sites_follow_the_code_not_its_line_numbers():
    for name in mutate.SELECTION:
        text = (FIRMWARE / mutate.BOARD / name).read_text()
        before = mutate.mutants_of(name, text)
        after = mutate.mutants_of(name, "/* a new comment */\n\n" + text)
        assert before, name
        assert [(m.function, m.kind, m.original, m.replacement, m.line + 2) for m in before] == \
               [(m.function, m.kind, m.original, m.replacement, m.line) for m in after]
    protect = (FIRMWARE / mutate.BOARD / "protect.c").read_text()
    compares = [m for m in mutate.mutants_of("protect.c", protect) if m.kind == "compare"]
    # every comparison operator in a function body (the file has none outside one but its #include <...>)
    code = [t for t in mutate.tokenize(protect) if not protect[protect.rfind("\n", 0, t.start) + 1:].startswith("#")]
    assert len({m.start for m in compares}) == sum(1 for t in code if t.kind == "op" and t.text in mutate.NEGATION)


def test_only_picks_files_and_line_ranges():
    every = mutate.all_mutants(FIRMWARE)
    picked = mutate.all_mutants(FIRMWARE, ["protect.c:1-40", "protect.c:100-120", "stage.c"], ("compare",))
    assert picked and {m.file for m in picked} == {"protect.c", "stage.c"}
    assert all(m.kind == "compare" for m in picked)
    assert all(m.file == "stage.c" or m.line <= 40 or 100 <= m.line <= 120 for m in picked)
    assert len([m for m in every if m.file == "stage.c" and m.kind == "compare"]) == \
           len([m for m in picked if m.file == "stage.c"])


def test_the_tests_that_killed_a_file_s_mutants_run_first_when_they_belong_to_the_step():
    killers = ["tests/firmware/test_fw_b6_limits.py::test_x", "tests/firmware/test_fw_b6_protect.py::test_y",
               "tests/firmware/test_fw_b6_acceptance.py::test_a_hang_ends[1]",
               "tests/firmware/test_fw_b6_acceptance.py::test_b_run"]
    assert mutate.first_tests(killers, mutate.SIM_TESTS[:2] + ["tests/firmware/test_fw_b6_acceptance.py::test_a_hang"]) \
        == [killers[0], killers[2]]
    assert mutate.first_tests(killers, mutate.HOST_TESTS) == [killers[1]]
