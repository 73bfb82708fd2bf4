"""Run the generated poller (FB_<DEV>_POLL) against the stub libraries: matiec compiles the poller's
matiec spelling with the device's plain-standard ST and a stub library (tests/support/st_stubs/), gcc
builds the C with a driver written here, and the driver plays the bus.

The driver keeps a register image per space (coils and discrete inputs as 0/1), calls the program that
calls the poller once per cycle, and after each cycle completes every stub request that has been busy
for a call: it copies the image into the buffer the poller passed (through the pointer, as the library
does), or writes the request's words into the image, or ends it with an injected fault (the request
number given: a reply timeout or an exception). It prints what the test reads back:

    req <n> <function> <address> <count> <outcome> <words...>   every request the bus saw, in order
    value <member>=<value> ...                                  the poller's stValues
    block <i> <decoded> <errors> <timeouts>                     the poller's per-block outputs
    passes <n>
    <label> <returned> <bRefused> <bPending> <bSent> <bDone> <bFailed> <bOutcomeUnknown>   a write step
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from regmap.backends.st.codec import IEC
from regmap.backends.st.device import device_views
from regmap.backends.st.poller import MATIEC, RUNTIMES, Runtime, poller
from regmap.model import Device
from regmap.render import templates

from support.st_exec import StProgram
from support.st_matiec import DRIVER_PRELUDE, Compiled, build_and_run, iec2c, program_text, st_files

STUBS = Path(__file__).resolve().parent / "st_stubs"
SPACES = ("coil", "discrete_input", "holding", "input")
FLAGS = ("-l", "-r", "-R")  # relaxed array equivalence (same-sized arrays passed), references, REF_TO ANY
OUTCOMES = {"ok": 0, "timeout": 1, "exception": 2}

# Per runtime and function code: the stub instance (in the poller's matiec spelling) and its fields.
CODESYS_FIELDS = {
    1: ("FBREADCOILS", "UISTARTITEM", "UIQUANTITY", "PDATA"),
    2: ("FBREADDISCRETEINPUTS", "UISTARTITEM", "UIQUANTITY", "PDATA"),
    3: ("FBREADHOLDINGREGISTERS", "UISTARTITEM", "UIQUANTITY", "PDATA"),
    4: ("FBREADINPUTREGISTERS", "UISTARTITEM", "UIQUANTITY", "PDATA"),
    5: ("FBWRITESINGLECOIL", "UIITEM", None, "XVALUE"),
    6: ("FBWRITESINGLEREGISTER", "UIITEM", None, "UIVALUE"),
    16: ("FBWRITEMULTIPLEREGISTERS", "UISTARTITEM", "UIQUANTITY", "PDATA"),
}
TWINCAT_ACTIONS = {
    1: "READCOILS",
    2: "READINPUTSTATUS",
    3: "READREGS",
    4: "READINPUTREGS",
    5: "WRITESINGLECOIL",
    6: "WRITESINGLEREGISTER",
    16: "WRITEREGS",
}
SPACE_OF = {1: 0, 2: 1, 3: 2, 4: 3, 5: 0, 6: 2, 16: 2}


@dataclass(frozen=True)
class WriteStep:
    """Call F_<DEV>_WRITE_<label>(args) between cycles, then run `cycles` more (a fault on the next request: `fault`)."""

    label: str
    function: str
    args: tuple[str, ...]  # C expressions, the ST inputs in order
    cycles: int
    fault: str = "ok"


@dataclass(frozen=True)
class Request:
    number: int
    function: int
    address: int
    count: int
    outcome: str
    words: tuple[int, ...]


@dataclass
class Run:
    requests: list[Request] = field(default_factory=list)
    values: dict[str, str] = field(default_factory=dict)
    blocks: list[tuple[bool, int, int]] = field(default_factory=list)
    passes: int = 0
    writes: dict[str, tuple[bool, ...]] = field(default_factory=dict)
    first_pass_end: int = 0  # requests before the values were printed (the write steps come after)


class PollBench:
    """One device's poller in one runtime's matiec spelling, compiled with that runtime's stubs."""

    def __init__(self, device: Device, runtime_name: str) -> None:
        self.device = device
        self.runtime: Runtime = next(r for r in RUNTIMES if r.name == runtime_name)
        self.views = device_views(device, IEC, [])
        self.poller = poller(self.views, self.runtime, MATIEC)
        self.program = StProgram(device)
        self.plan = self.views["plan"]
        self.write_type: str = self.views["write"].type_name

    def poll_text(self) -> str:
        return templates("regmap.backends.st").get_template("poll.st.jinja").render(**self.views, runtime=self.runtime, poller=self.poller)

    def source(self, poll_text: str | None = None, high_word_first: bool = True, inputs: Sequence[str] = ()) -> str:
        """`inputs`: more of the poller's inputs, as ST arguments (`dwVariant := ...`)."""
        stubs = (STUBS / f"vendor_stubs_{self.runtime.name}.st").read_text(encoding="utf-8")
        client = self.runtime.name == "codesys"
        args = ["bEnable := TRUE", "nUnitId := 1", *inputs]
        if any(m.name == "bHighWordFirst" for m in self.poller.inputs):
            args.append(f"bHighWordFirst := {'TRUE' if high_word_first else 'FALSE'}")
        args.append("stWrite := stWrite")
        if client:
            args.append("rClient := stClient")
        program = "\n".join(
            [
                stubs,
                poll_text if poll_text is not None else self.poll_text(),
                "PROGRAM P_POLL",
                "VAR",
                f"    fbPoll : {self.poller.name};",
                f"    stWrite : {self.write_type};",
                *(["    stClient : Client;"] if client else []),
                "END_VAR",
                f"fbPoll({', '.join(args)});",
                "END_PROGRAM",
                "",
            ]
        )
        return program_text(st_files(self.device), program, "P_POLL")

    def compile(
        self,
        matiec: Path,
        work: Path,
        poll_text: str | None = None,
        name: str = "poll",
        high_word_first: bool = True,
        inputs: Sequence[str] = (),
    ) -> Compiled:
        source = self.source(poll_text, high_word_first, inputs)
        return iec2c(matiec, source, work, f"{self.device.id}_{self.runtime.name}_{name}", FLAGS)

    # -- the driver --------------------------------------------------------------------------

    def _serve(self, code: int) -> list[str]:
        """C that completes the stub request of function `code` when it has been busy for a call."""
        bits = code in (1, 2, 5)
        if self.runtime.name == "codesys":
            instance, addr, count, data = CODESYS_FIELDS[code]
            path = f"prog.FBPOLL.{instance}"
            busy, done = f"{path}.XBUSY.value", [f"{path}.XBUSY.value = 0;"]
            count_expr = f"{path}.{count}.value" if count else "1"
            ok = [f"{path}.XDONE.value = 1;"]
            timeout = [f"{path}.XERROR.value = 1;", f"{path}.EERRORID.value = ERROR__REPLYTIMEOUT;"]
            exception = [f"{path}.XERROR.value = 1;", f"{path}.EERRORID.value = ERROR__REQUESTEXCEPTION;"]
            if code in (1, 2):
                read = [
                    f"{{ BOOL *p = (BOOL *){path}.{data}.value; for (i = 0; i < n; i++) p[i] = image[{SPACE_OF[code]}][a + i] ? 1 : 0; }}"
                ]
            elif code in (3, 4):
                read = [f"{{ UINT *p = (UINT *){path}.{data}.value; for (i = 0; i < n; i++) p[i] = image[{SPACE_OF[code]}][a + i]; }}"]
            else:
                read = []
            if code == 5:
                words = [f"w[0] = {path}.{data}.value ? 0xFF00u : 0u;"]
            elif code == 6:
                words = [f"w[0] = {path}.{data}.value;"]
            else:
                words = [f"{{ UINT *p = (UINT *){path}.{data}.value; for (i = 0; i < n && i < 125; i++) w[i] = p[i]; }}"]
            addr_expr = f"{path}.{addr}.value"
            cycles = f"{path}.NCYCLES.value"
        else:
            path = f"prog.FBPOLL.FB{TWINCAT_ACTIONS[code]}"
            busy, done = f"{path}.BUSY.value", [f"{path}.BUSY.value = 0;"]
            count_expr = f"{path}.QUANTITY.value"
            ok = [f"{path}.CBREAD.value = {'(n + 7) / 8' if bits else '2 * n'};"]
            timeout = [f"{path}.ERROR.value = 1;", f"{path}.ERRORID.value = MODBUS_ERRORS__MODBUSERROR_NO_RESPONSE;"]
            exception = [f"{path}.ERROR.value = 1;", f"{path}.ERRORID.value = MODBUS_ERRORS__MODBUSERROR_ILLEGAL_DATA_ADDRESS;"]
            pointer = f"{path}.PMEMORYADDR.value"
            if code in (1, 2):
                read = [
                    f"{{ BYTE *p = (BYTE *){pointer}; for (i = 0; i < (n + 7) / 8; i++) p[i] = 0;",
                    f"  for (i = 0; i < n; i++) if (image[{SPACE_OF[code]}][a + i]) p[i / 8] |= (BYTE)(1u << (i % 8)); }}",
                ]
            elif code in (3, 4):
                read = [f"{{ WORD *p = (WORD *){pointer}; for (i = 0; i < n; i++) p[i] = image[{SPACE_OF[code]}][a + i]; }}"]
            else:
                read = []
            if code == 5:
                words = [f"w[0] = (((BYTE *){pointer})[0] & 1) ? 0xFF00u : 0u;"]
            else:
                words = [f"{{ WORD *p = (WORD *){pointer}; for (i = 0; i < n && i < 125; i++) w[i] = p[i]; }}"]
            addr_expr = f"{path}.MBADDR.value"
            cycles = f"{path}.NCYCLES.value"
        write = code in (5, 6, 16)
        return [
            f"if ({busy} && {cycles} >= 1) {{",
            f"    unsigned a = {addr_expr}, n = {count_expr}; WORD w[125]; int outcome;",
            "    memset(w, 0, sizeof w);",
            *(f"    {line}" for line in (words if write else [])),
            f"    outcome = next_outcome({int(write)});",
            *(f"    {line}" for line in done),
            "    if (outcome == 1) {",
            *(f"        {line}" for line in timeout),
            "    } else if (outcome == 2) {",
            *(f"        {line}" for line in exception),
            "    } else {",
            *(f"        {line}" for line in ok + read),
            *(
                [f"        for (i = 0; i < n; i++) image[{SPACE_OF[code]}][a + i] = {'w[0] ? 1 : 0' if code == 5 else 'w[i]'};"]
                if write
                else []
            ),
            "    }",
            f'    printf("req %d {code} %u %u %s", requests, a, n, outcome == 1 ? "timeout" : outcome == 2 ? "exception" : "ok");',
            f'    for (i = 0; i < {"(int)n" if write else "0"}; i++) printf(" %u", (unsigned)w[i]);',
            '    printf("\\n");',
            "}",
        ]

    def driver(self, image: dict[str, dict[int, int]], faults: dict[int, str], cycles: int, steps: Sequence[WriteStep]) -> str:
        codes = self.poller.functions
        fill = [
            f"image[{SPACES.index(space)}][{address}] = {word}u;"
            for space, words in image.items()
            for address, word in sorted(words.items())
        ]
        n = len(self.plan)
        values = self.views["values"].type_name
        step_lines: list[str] = []
        for step in steps:
            step_lines += [
                f"forced = {OUTCOMES[step.fault]};",
                f"ok = {step.function}(1, &eno, {', '.join(step.args)}, &prog.STWRITE.value);",
                f'print_write("{step.label}", ok, &prog.STWRITE.value);',
                f"run({step.cycles});",
                f'print_write("{step.label}_after", ok, &prog.STWRITE.value);',
            ]
        member_prints = [self.program._print_member(m.name) for m in self.views["values"].members]
        return "\n".join(
            [
                *DRIVER_PRELUDE,
                "static WORD image[4][65536];",
                "static P_POLL prog;",
                "static int requests = 0, forced = -1;",
                f"static const int faults[] = {{{', '.join(f'{k}, {OUTCOMES[v]}' for k, v in sorted(faults.items()))}{', ' if faults else ''}0, 0}};",
                "static int next_outcome(int write) {",
                "    int k;",
                "    requests++;",
                "    if (write && forced >= 0) { k = forced; forced = -1; return k; }  /* a write step's fault: its own write */",
                "    for (k = 0; faults[k] != 0; k += 2) if (faults[k] == requests) return faults[k + 1];",
                "    return 0;",
                "}",
                "static void bus(void) {",
                "    int i;",
                "    (void)i;",
                *(f"    {line}" for code in codes for line in self._serve(code)),
                "}",
                "static void run(int cycles) {",
                "    int c;",
                "    for (c = 0; c < cycles; c++) { P_POLL_body__(&prog); bus(); }",
                "}",
                f"static void print_write(const char *label, BOOL ok, {self.write_type} *w) {{",
                '    printf("%s %d %d %d %d %d %d %d\\n", label, (int)ok, (int)w->BREFUSED, (int)w->BPENDING, (int)w->BSENT,',
                "           (int)w->BDONE, (int)w->BFAILED, (int)w->BOUTCOMEUNKNOWN);",
                "}",
                "int main(void) {",
                "    BOOL ok, eno;",
                f"    {values} v;",
                "    int i;",
                "    (void)ok; (void)eno; (void)i;",
                *(f"    {line}" for line in fill),
                "    P_POLL_init__(&prog, 0);",
                f"    for (i = 0; i < {cycles} && prog.FBPOLL.NPASSES.value < 2; i++) {{ P_POLL_body__(&prog); bus(); }}",
                "    v = prog.FBPOLL.STVALUES.value;",
                '    printf("value");',
                *(f"    {line}" for line in member_prints),
                '    printf("\\n");',
                f"    for (i = 0; i < {n}; i++)",
                '        printf("block %d %d %u %u\\n", i, (int)prog.FBPOLL.ADECODED.value.table[i],',
                "               (unsigned)prog.FBPOLL.AERRORS.value.table[i], (unsigned)prog.FBPOLL.ATIMEOUTS.value.table[i]);",
                '    printf("passes %u\\n", (unsigned)prog.FBPOLL.NPASSES.value);',
                *(f"    {line}" for line in step_lines),
                "    return 0;",
                "}",
                "",
            ]
        )

    def run(
        self,
        matiec: Path,
        work: Path,
        image: dict[str, dict[int, int]],
        faults: dict[int, str],
        steps: Sequence[WriteStep] = (),
        cycles: int = 20000,
        high_word_first: bool = True,
        inputs: Sequence[str] = (),
    ) -> Run:
        """`high_word_first`: the poller's bHighWordFirst, for a device whose word order is a parameter; `inputs`: more
        of its inputs, as ST arguments."""
        compiled = self.compile(matiec, work, high_word_first=high_word_first, inputs=inputs)
        assert compiled.returncode == 0 and not compiled.errors, compiled.output[-3000:]
        stdout = build_and_run(
            matiec, compiled, self.driver(image, faults, cycles, steps), work / f"{self.device.id}_{self.runtime.name}_poll"
        )
        return parse(stdout, {s.label for s in steps})


def parse(stdout: str, labels: set[str]) -> Run:
    run = Run()
    for line in stdout.splitlines():
        kind, *rest = line.split(" ")
        if kind == "req":
            number, function, address, count, outcome, *words = rest
            run.requests.append(Request(int(number), int(function), int(address), int(count), outcome, tuple(int(w) for w in words)))
        elif kind == "value":
            run.first_pass_end = len(run.requests)
            run.values = dict(item.split("=", 1) for item in rest if item)
        elif kind == "block":
            run.blocks.append((rest[1] == "1", int(rest[2]), int(rest[3])))
        elif kind == "passes":
            run.passes = int(rest[0])
        elif kind.removesuffix("_after") in labels:
            run.writes[kind] = tuple(flag == "1" for flag in rest)
    return run
