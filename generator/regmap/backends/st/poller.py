"""The polling function block of one device, `FB_<DEV>_POLL`, for the two runtimes PLC users have:
CODESYS (the ModbusFB library: a `ModbusFB.ClientSerial` or `ClientTcp` passed in, one request block per
function code) and TwinCAT 3 (Tc2_ModbusRTU: a `ModbusRtuMaster_KL6x5B` passed in, one action per
function code). Both run one logic, computed here once:

- it walks the read-plan blocks in order (a static block until it has been read once, a
  firmware-gated block only while the connected firmware has it), one request at a time, with
  Execute high until the request ends and low for one call to release it;
- a block read fills the block's raw struct and decodes it with the block's decoder into `stValues`
  (`aDecoded[i]`: what the decoder returned); a failed read counts in `aTimeouts[i]` (no reply) or
  `aErrors[i]` (an exception or any other failure), and leaves the values as they were;
- a write waiting in `stWrite` (only an encoder's accepted words get there, see writes.py) goes first,
  once: `bSent` as it leaves, then `bDone`, `bFailed` (an exception reply: not done) or
  `bOutcomeUnknown` (no valid reply: perhaps done). No retry: the library's own retries stay 0.

The call of each library block is the runtime's; `Spelling` says how it is written: `VENDOR` is the
text the runtime's IDE reads, `MATIEC` the same logic as matiec (OpenPLC's compiler) reads it, for the
tests that compile the poller against stub libraries with the vendors' interfaces
(tests/support/st_stubs/): no namespaces, no actions (each action a block of the master's interface),
references (`REF_TO`, `REF()`) for pointers, a literal for SIZEOF, `TYPE#VALUE` for enum values, and
the client a struct (matiec 6bb2c33 crashes on a function block in VAR_IN_OUT).
"""

from __future__ import annotations

from typing import Any

from regmap.backends.st.codec import NATURAL
from regmap.backends.st.functions import Block, plan_blocks
from regmap.backends.st.names import st_hex, st_int
from regmap.backends.st.view_types import Member
from regmap.backends.st.views import VARIANT_TYPE, Names, firmware_raw, variants_mask
from regmap.backends.st.writes import WRITE_COIL, WRITE_MULTIPLE, WRITE_SINGLE
from regmap.model import Device, PollClass
from regmap.records import cached_property, dataclass

READ_COILS, READ_DISCRETE, READ_HOLDING, READ_INPUT = 0x01, 0x02, 0x03, 0x04
BIT_FUNCTIONS = frozenset({READ_COILS, READ_DISCRETE, WRITE_COIL})
VARIANT_INPUT = "dwVariant"  # the connected variant's bit, 0 while it is not known


@dataclass(frozen=True)
class Spelling:
    vendor: bool

    def qualified(self, namespace: str, name: str) -> str:
        return f"{namespace}.{name}" if self.vendor and namespace else name

    def enum(self, namespace: str, type_name: str, member: str) -> str:
        return f"{self.qualified(namespace, type_name)}.{member}" if self.vendor else f"{type_name}#{member}"

    def address(self, buffer: str) -> str:
        return f"ADR({buffer})" if self.vendor else f"REF({buffer}[0])"

    def size(self, buffer: str, size: int) -> str:
        return f"SIZEOF({buffer})" if self.vendor else st_int(size)


VENDOR = Spelling(True)
MATIEC = Spelling(False)


@dataclass(frozen=True)
class Buffers:
    """The poller's request buffers: `aWords` for registers, `aBits` for coils and discrete inputs."""

    words: int
    bits: int  # 0: the map has no bit space


@dataclass(frozen=True)
class Codesys:
    """CODESYS V3, library ModbusFB (ModbusFB.ClientSerial / ClientTcp and the ClientRequest… blocks)."""

    name: str = "codesys"
    title: str = "CODESYS V3 (library ModbusFB)"
    word_type: str = "UINT"  # pData : POINTER TO ARRAY [0..0] OF UINT
    bit_type: str = "BOOL"  # pData : POINTER TO ARRAY [0..0] OF BOOL, one BOOL per coil
    sources: tuple[str, ...] = (
        "https://content.helpme-codesys.com/en/libs/ModbusFB/Current/ModbusFB/fld-ModbusFB.html",
        "https://content.helpme-codesys.com/en/libs/ModbusFB/Current/ModbusFB/Function-Blocks/Client/ClientRequest.html",
        "https://content.helpme-codesys.com/en/libs/ModbusFB/4.3.0.0/ModbusFB/Enums/Error.html",
    )
    namespace: str = "ModbusFB"
    blocks: tuple[tuple[int, str, str], ...] = (
        (READ_COILS, "fbReadCoils", "ClientRequestReadCoils"),
        (READ_DISCRETE, "fbReadDiscreteInputs", "ClientRequestReadDiscreteInputs"),
        (READ_HOLDING, "fbReadHoldingRegisters", "ClientRequestReadHoldingRegisters"),
        (READ_INPUT, "fbReadInputRegisters", "ClientRequestReadInputRegisters"),
        (WRITE_COIL, "fbWriteSingleCoil", "ClientRequestWriteSingleCoil"),
        (WRITE_SINGLE, "fbWriteSingleRegister", "ClientRequestWriteSingleRegister"),
        (WRITE_MULTIPLE, "fbWriteMultipleRegisters", "ClientRequestWriteMultipleRegisters"),
    )

    def inputs(self) -> list[Member]:
        return [
            Member("nUnitId", "UINT", "the device's slave id (uiUnitId)"),
            Member("udiReplyTimeout", "UDINT := 1000000", "µs to wait for a reply (ModbusFB's default is 50 ms)"),
        ]

    def in_outs(self, s: Spelling) -> list[Member]:
        return [Member("rClient", s.qualified(self.namespace, "Client"), "the ModbusFB.ClientSerial (or ClientTcp) of the bus, connected")]

    def locals(self, functions: set[int], s: Spelling) -> list[Member]:
        return [Member(instance, s.qualified(self.namespace, kind)) for code, instance, kind in self.blocks if code in functions]

    def call(self, function: int, buffers: Buffers, s: Spelling) -> tuple[list[str], list[str]]:
        """(the call, the statements that read its outcome into bFinished, bFailed, bTimedOut, bException)."""
        instance = next(i for code, i, _ in self.blocks if code == function)
        args = [
            "rClient := rClient",
            "uiUnitId := nUnitId",
            "udiReplyTimeout := udiReplyTimeout",
            "uiMaxRetries := 0",  # a write is sent once; a read is retried by the next pass
        ]
        if function in (READ_COILS, READ_DISCRETE):
            args += ["uiStartItem := nAddr", "uiQuantity := nCount", f"pData := {s.address('aBits')}"]
        elif function in (READ_HOLDING, READ_INPUT, WRITE_MULTIPLE):
            args += ["uiStartItem := nAddr", "uiQuantity := nCount", f"pData := {s.address('aWords')}"]
        elif function == WRITE_SINGLE:
            args += ["uiItem := nAddr", "uiValue := aWords[0]"]
        else:
            args += ["uiItem := nAddr", "xValue := aBits[0]"]
        args.append("xExecute := bExecute")
        error = f"{instance}.eErrorID"
        return [f"{instance}({', '.join(args)});"], [
            f"bFinished := {instance}.xDone OR {instance}.xError;",
            f"bFailed := {instance}.xError;",
            f"bTimedOut := {error} = {s.enum(self.namespace, 'Error', 'ReplyTimeout')};",
            f"bException := {error} = {s.enum(self.namespace, 'Error', 'RequestException')};",
        ]

    def coil_byte(self, on: str) -> str:
        return on


# Tc2_ModbusRTU's MODBUS_ERRORS that carry an exception reply (the device answered: the request was not done).
TWINCAT_EXCEPTIONS = (
    "MODBUSERROR_ILLEGAL_FUNCTION",
    "MODBUSERROR_ILLEGAL_DATA_ADDRESS",
    "MODBUSERROR_ILLEGAL_DATA_VALUE",
    "MODBUSERROR_SLAVE_DEVICE_FAILURE",
    "MODBUSERROR_ACKNOWLEDGE",
    "MODBUSERROR_SLAVE_DEVICE_BUSY",
    "MODBUSERROR_NEGATIVE_ACKNOWLEDGE",
    "MODBUSERROR_MEMORY_PARITY",
    "MODBUSERROR_GATEWAY_PATH_UNAVAILABLE",
    "MODBUSERROR_GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND",
)


@dataclass(frozen=True)
class Twincat:
    """TwinCAT 3, library Tc2_ModbusRTU (ModbusRtuMaster_KL6x5B; ModbusRtuMaster_PcCOM has the same actions)."""

    name: str = "twincat"
    title: str = "TwinCAT 3 (library Tc2_ModbusRTU)"
    word_type: str = "WORD"
    bit_type: str = "BYTE"  # pMemoryAddr : POINTER TO BYTE, 8 coils per byte
    sources: tuple[str, ...] = (
        "https://infosys.beckhoff.com/content/1033/tf6255_tc3_modbus_rtu/186539275.html",
        "https://infosys.beckhoff.com/content/1033/tf6255_tc3_modbus_rtu/186558219.html",
    )
    master_type: str = "ModbusRtuMaster_KL6x5B"
    actions: tuple[tuple[int, str], ...] = (
        (READ_COILS, "ReadCoils"),
        (READ_DISCRETE, "ReadInputStatus"),
        (READ_HOLDING, "ReadRegs"),
        (READ_INPUT, "ReadInputRegs"),
        (WRITE_COIL, "WriteSingleCoil"),
        (WRITE_SINGLE, "WriteSingleRegister"),
        (WRITE_MULTIPLE, "WriteRegs"),
    )

    def inputs(self) -> list[Member]:
        return [
            Member("nUnitId", "UINT", "the device's slave id (UnitID)"),
            Member("tReplyTimeout", "TIME := T#1S", "time to wait for a reply (Timeout)"),
        ]

    def in_outs(self, s: Spelling) -> list[Member]:
        if not s.vendor:
            return []
        return [Member("fbMaster", self.master_type, "the bus master, linked to its KL6001/KL6011/KL6021 terminal")]

    def locals(self, functions: set[int], s: Spelling) -> list[Member]:
        if s.vendor:
            return []
        return [Member(f"fb{action}", action) for code, action in self.actions if code in functions]

    def call(self, function: int, buffers: Buffers, s: Spelling) -> tuple[list[str], list[str]]:
        """(the call, the statements that read its outcome into bFinished, bFailed, bTimedOut, bException)."""
        action = dict(self.actions)[function]
        instance = "fbMaster" if s.vendor else f"fb{action}"
        call = f"fbMaster.{action}" if s.vendor else instance
        bits = function in BIT_FUNCTIONS
        buffer, size = ("aBits", buffers.bits) if bits else ("aWords", 2 * buffers.words)
        args = [
            "UnitID := nUnitId",
            "Quantity := UINT_TO_WORD(nCount)",
            "MBAddr := UINT_TO_WORD(nAddr)",
            f"cbLength := {s.size(buffer, size)}",
            f"pMemoryAddr := {s.address(buffer)}",
            "Execute := bExecute",
            "Timeout := tReplyTimeout",
        ]
        error = f"{instance}.ErrorId"
        exception = " OR ".join(f"{error} = {s.enum('', 'MODBUS_ERRORS', e)}" for e in TWINCAT_EXCEPTIONS)
        return [f"{call}({', '.join(args)});"], [
            f"IF {instance}.BUSY THEN",
            "    bStarted := TRUE;",
            "END_IF;",
            f"bFinished := bStarted AND NOT {instance}.BUSY;",
            f"bFailed := {instance}.Error;",
            f"bTimedOut := {error} = {s.enum('', 'MODBUS_ERRORS', 'MODBUSERROR_NO_RESPONSE')};",
            f"bException := {exception};",
        ]

    def coil_byte(self, on: str) -> str:
        return f"BOOL_TO_BYTE({on})"


def serial_settings(device: Any) -> dict[str, str]:
    """The SysCom values of ModbusFB.ClientSerial's inputs for the device's serial line (the README's example)."""
    t = device.transport
    parity = {"none": "SYS_NOPARITY", "even": "SYS_EVENPARITY", "odd": "SYS_ODDPARITY"}[t.parity]
    stop = {1: "SYS_ONESTOPBIT", 2: "SYS_TWOSTOPBITS"}[t.stop_bits]
    return {"baud": f"SysCom.SYS_BR_{t.baud}", "parity": f"SysCom.{parity}", "stop": f"SysCom.{stop}"}


Runtime = Codesys | Twincat
RUNTIMES: tuple[Runtime, ...] = (Codesys(), Twincat())


@dataclass(frozen=True)
class Poller:
    name: str
    comment: str
    inputs: tuple[Member, ...]
    in_outs: tuple[Member, ...]
    outputs: tuple[Member, ...]
    locals: tuple[Member, ...]
    body: tuple[str, ...]
    functions: tuple[int, ...]  # the Modbus function codes it sends

    @cached_property
    def body_text(self) -> str:
        """The statements, one a line (thousands: joined here, not looped over in the template)."""
        return "".join([f"{line}\n" for line in self.body])


def _convert(value: str, source: str, target: str) -> str:
    return value if source == target else f"{source}_TO_{target}({value})"


def _loop(count: int, body: list[str], start: int = 0) -> list[str]:
    """k from `start` to `start + count - 1`: a WHILE, since matiec 6bb2c33 runs `FOR k := 0 TO 0` no time at all."""
    return [f"k := {start};", f"WHILE k < {start + count} DO", *(f"    {line}" for line in body), "    k := k + 1;", "END_WHILE;"]


def _copy_in(block: Block, raw: str, runtime: Runtime, indent: str = "") -> list[str]:
    """Statements that fill the block's raw struct from the request buffer, member by member in wire order, each
    after `indent` (made indented here: a block has a statement per word, each runtime's poller copies every block)."""
    if block.bits:
        count = block.count
        if runtime.bit_type == "BYTE":  # packed as the response carries them
            looped = _loop((count + 7) // 8, [f"{raw}.BITS[k] := aBits[k];"])
        else:
            looped = _loop((count + 7) // 8, [f"{raw}.BITS[k] := 0;"]) + _loop(
                count, ["IF aBits[k] THEN", f"    {raw}.BITS[k / 8] := {raw}.BITS[k / 8] OR SHL(BYTE#1, k MOD 8);", "END_IF;"]
            )
        return [f"{indent}{line}" for line in looped]
    lines = []
    at = 0
    # an array's elements are WORDs: the buffer's word converted to WORD the same way for each (`_convert`)
    before, after = ("", "") if runtime.word_type == "WORD" else (f"{runtime.word_type}_TO_WORD(", ")")
    for member in block.struct.members:
        target = f"{indent}{raw}.{member.name}"
        if member.type.startswith("ARRAY["):
            count = int(member.type.split("..")[1].split("]")[0]) + 1
            lines += [f"{target}[{j}] := {before}aWords[{at + j}]{after};" for j in range(count)]
            at += count
        else:
            lines.append(f"{target} := {_convert(f'aWords[{at}]', runtime.word_type, member.type)};")
            at += 1
    return lines


def _due(names: Names, index: int, poll: PollClass, gate: Any, variants: tuple[str, ...]) -> str | None:
    """The condition under which block `index` is read (None: every pass)."""
    parts = []
    if poll is PollClass.STATIC:
        parts.append(f"NOT aHave[{index}]")
    on_variant = _on_variant(names.device, variants)
    if on_variant is not None:
        parts.append(on_variant)
    if gate is not None:
        first = firmware_raw(names, gate.first) if gate.first else None
        until = firmware_raw(names, gate.until) if gate.until else None
        if (gate.first and first is None) or (gate.until and until is None):
            return "FALSE (* the firmware reports its version as text: compare it yourself *)"
        parts.append("bFirmwareKnown")
        if first is not None:
            parts.append(f"nFirmware >= {st_int(first)}")
        if until is not None:
            parts.append(f"nFirmware < {st_int(until)}")
    return " AND ".join(parts) if parts else None


def _on_variant(device: Device, variants: tuple[str, ...]) -> str | None:
    """When the poller reads a block of `variants` (None: always): the connected variant is one of them, or
    not known (then every block is read, as the Python client without `variant=` reads every register)."""
    if not variants:
        return None
    mask = st_hex(variants_mask(device, variants), 8)
    return f"({VARIANT_INPUT} = 0 OR ({VARIANT_INPUT} AND {mask}) <> 0)"


def _advance(n: int) -> list[str]:
    return ["nBlock := nBlock + 1;", f"IF nBlock >= {n} THEN", "    nBlock := 0;", "    nPasses := nPasses + 1;", "END_IF;"]


def _choose(names: Names, plan: list[Block], planned: list[Any], runtime: Runtime, functions: set[int], words_in_write: int) -> list[str]:
    """Step 1: pick the next request (a waiting write first, else the next due block) and set it up."""
    n = len(plan)
    advance = _advance(n)
    due_cases = [(i, _due(names, i, poll, gate, variants)) for i, (_, poll, gate, variants) in enumerate(planned)]
    due_cases = [(i, c) for i, c in due_cases if c is not None]
    search = ["bDue := TRUE;"]  # every block is due on every pass
    if due_cases:
        search = [
            "bDue := FALSE;",
            *_loop(
                n,
                [
                    "bDue := TRUE;",
                    "CASE nBlock OF",
                    *(f"    {i}: bDue := {c};" for i, c in due_cases),
                    "END_CASE;",
                    "IF bDue THEN",
                    "    EXIT;",
                    "END_IF;",
                    *advance,
                ],
            ),
        ]
    coil_write = []
    if WRITE_COIL in functions:
        coil_write = [f"aBits[0] := {runtime.coil_byte('stWrite.aWords[0] = 16#FF00')};"]
    return [
        "(* 1. the next request: a waiting write first (sent once), else the next block that is due *)",
        "IF nState = 0 THEN",
        "    IF stWrite.bPending THEN",
        "        stWrite.bPending := FALSE;",
        "        stWrite.bSent := TRUE;",
        "        nRequest := -1;",
        "        nFunction := stWrite.nFunction;",
        "        nAddr := stWrite.nAddr;",
        "        nCount := stWrite.nCount;",
        *(f"        aWords[{k}] := {_convert(f'stWrite.aWords[{k}]', 'WORD', runtime.word_type)};" for k in range(words_in_write)),
        *(f"        {line}" for line in coil_write),
        "        nState := 1;",
        "    ELSIF bEnable THEN",
        *(f"        {line}" for line in search),
        "        IF bDue THEN",
        "            nRequest := nBlock;",
        "            CASE nBlock OF",
        *(
            f"                {i}: nFunction := {st_hex(b.function, 2)}; nAddr := {st_hex(b.address)}; nCount := {st_int(b.count)};"
            for i, b in enumerate(plan)
        ),
        "            END_CASE;",
        "            nState := 1;",
        "        END_IF;",
        "    END_IF;",
        "    IF nState = 1 THEN",
        "        bExecute := TRUE;",
        "        bStarted := FALSE;",
        "    END_IF;",
        "END_IF;",
        "(* 2. call the request's block: Execute high until it ends, then low for one call *)",
        "IF nState > 0 THEN",
        "    bFinished := FALSE;",
        "    CASE nFunction OF",
    ]


def _run(plan: list[Block], planned: list[Any], runtime: Runtime, spelling: Spelling, functions: set[int], buffers: Buffers) -> list[str]:
    """Step 2: call the running request's block, then take its outcome (the write's flags, a block's counters or values)."""
    advance = _advance(len(plan))
    body: list[str] = []
    calls = {code: runtime.call(code, buffers, spelling) for code in sorted(functions)}
    shared = len({tuple(outcome) for _, outcome in calls.values()}) == 1  # one master: its outputs after any call
    for code, (call, outcome) in calls.items():
        body.append(f"        {st_int(code)}:")
        body += [f"            {line}" for line in (call if shared else call + outcome)]
    body.append("    END_CASE;")
    if shared:
        body += [f"    {line}" for line in next(iter(calls.values()))[1]]
    body += [
        "    IF nState = 2 THEN",
        "        nState := 0;",
        "    ELSIF bFinished THEN",
        "        bExecute := FALSE;",
        "        nState := 2;",
        "        IF nRequest < 0 THEN",
        "            IF NOT bFailed THEN",
        "                stWrite.bDone := TRUE;",
        "            ELSIF bException THEN",
        "                stWrite.bFailed := TRUE;",
        "            ELSE",
        "                stWrite.bOutcomeUnknown := TRUE; (* no valid reply: perhaps written; never sent again *)",
        "            END_IF;",
        "        ELSIF bFailed THEN",
        "            IF bTimedOut THEN",
        "                aTimeouts[nRequest] := aTimeouts[nRequest] + 1;",
        "            ELSE",
        "                aErrors[nRequest] := aErrors[nRequest] + 1;",
        "            END_IF;",
        "        ELSE",
        "            CASE nRequest OF",
    ]
    for i, b in enumerate(plan):
        raw = f"stRaw{i}"
        order_arg = ", bHighWordFirst := bHighWordFirst" if len(b.decode.inputs) > 1 else ""
        body.append(f"                {i}:")
        body += _copy_in(b, raw, runtime, "                    ")
        body.append(f"                    aDecoded[{i}] := {b.decode.name}(stRaw := {raw}{order_arg}, stValues := stValues);")
        if planned[i][1] is PollClass.STATIC:
            body.append(f"                    aHave[{i}] := TRUE;")
    body += [
        "            END_CASE;",
        "        END_IF;",
        "        IF nRequest >= 0 THEN",
        *(f"            {line}" for line in advance),
        "        END_IF;",
        "    END_IF;",
        "END_IF;",
    ]
    return body


def poller(context: dict[str, Any], runtime: Runtime, spelling: Spelling) -> Poller:
    """FB_<DEV>_POLL of one device (the views of `context`, any dialect: the names are the same)."""
    device = context["device"]
    names: Names = context["names"]
    plan: list[Block] = context["plan"]
    write = context["write"]
    words_in_write = int(write.members[-1].type.split("..")[1].split("]")[0]) + 1
    planned = plan_blocks(device)
    writable_spaces = {r.space for r in device.registers if r.access.writable}
    functions = {b.function for b in plan}
    if "holding" in writable_spaces:
        functions |= {WRITE_SINGLE, WRITE_MULTIPLE}
    if "coil" in writable_spaces:
        functions.add(WRITE_COIL)
    buffers = Buffers(
        max([b.count for b in plan if not b.bits] + [words_in_write]),
        max([b.count for b in plan if b.bits] + ([1] if WRITE_COIL in functions else [0])),
    )
    if runtime.bit_type == "BYTE" and buffers.bits:
        buffers = Buffers(buffers.words, (buffers.bits + 7) // 8)
    n = len(plan)
    name = names.type("FB", "POLL", what="the poller")
    order = context["order_input"]
    firmware = device.info.firmware_register
    gated = any(gate is not None for _, _, gate, _ in planned)
    static = any(poll is PollClass.STATIC for _, poll, _, _ in planned)

    inputs = [Member("bEnable", "BOOL", "TRUE: read the blocks over and over"), *runtime.inputs()]
    if order:
        inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter, as configured"))
    if gated and firmware is not None and firmware.register.type.numeric:
        inputs += [
            Member("bFirmwareKnown", "BOOL", f"nFirmware holds {firmware.register.name} as the device reported it"),
            Member("nFirmware", NATURAL[firmware.register.type], f"the raw {firmware.register.name}: gated blocks follow it"),
        ]
    if any(variants for _, _, _, variants in planned):
        inputs.append(
            Member(VARIANT_INPUT, VARIANT_TYPE, "the connected variant's VARIANT bit: blocks it lacks are skipped (0: not known, all read)")
        )
    in_outs = [Member("stWrite", write.type_name, "a setting from F_..._WRITE_...: sent once"), *runtime.in_outs(spelling)]
    outputs = [
        Member("stValues", context["values"].type_name, "the decoded values"),
        Member("aDecoded", f"ARRAY[0..{n - 1}] OF BOOL", "per block: read, and every value in it valid"),
        Member("aErrors", f"ARRAY[0..{n - 1}] OF UDINT", "per block: failed reads other than timeouts"),
        Member("aTimeouts", f"ARRAY[0..{n - 1}] OF UDINT", "per block: reads without a reply in time"),
        Member("nPasses", "UDINT", "complete walks over the read plan"),
    ]
    local = [
        Member("nState", "INT", "0 idle, 1 a request running, 2 releasing it (Execute low)"),
        Member("nBlock", "INT", "the next block to read"),
        Member("nRequest", "INT", "the running request: a block, or -1 for the write"),
        Member("nFunction", "USINT"),
        Member("nAddr", "UINT"),
        Member("nCount", "UINT"),
        Member("bExecute", "BOOL"),
        Member("bStarted", "BOOL"),
        Member("bFinished", "BOOL"),
        Member("bFailed", "BOOL"),
        Member("bTimedOut", "BOOL"),
        Member("bException", "BOOL"),
        Member("bDue", "BOOL"),
        Member("k", "INT"),
        Member("aWords", f"ARRAY[0..{buffers.words - 1}] OF {runtime.word_type}"),
    ]
    if buffers.bits:
        local.append(Member("aBits", f"ARRAY[0..{buffers.bits - 1}] OF {runtime.bit_type}"))
    if static:
        local.append(Member("aHave", f"ARRAY[0..{n - 1}] OF BOOL", "a static block read once"))
    local += runtime.locals(functions, spelling)
    local += [Member(f"stRaw{i}", b.struct.type_name) for i, b in enumerate(plan)]

    body = _choose(names, plan, planned, runtime, functions, words_in_write) + _run(plan, planned, runtime, spelling, functions, buffers)
    comment = (
        f"Polls {device.id} through {runtime.title}: the {n} read-plan blocks in turn into stValues, "
        "errors and timeouts counted per block, and the write waiting in stWrite sent once (never retried)."
    )
    return Poller(name, comment, tuple(inputs), tuple(in_outs), tuple(outputs), tuple(local), tuple(body), tuple(sorted(functions)))
