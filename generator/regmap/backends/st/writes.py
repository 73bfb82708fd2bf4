"""The settings a PLC sends through the poller: `ST_<DEV>_WRITE` (one write waiting, and how the last
one ended) and an `F_<DEV>_WRITE_<X>` per encoder, which fills it only with what the encoder accepts.

A write request exists only through its encoder: a value the encoder refuses (out of range, not a
member, a state the device only reports, a destructive command's value) sets `bRefused` and leaves
nothing to send. The poller sends a waiting write once and never again: a reply that does not come is
`bOutcomeUnknown` (the device may have done it), as the Python client raises OutcomeUnknown.
"""

from __future__ import annotations

from regmap.backends.st.names import st_hex, st_int
from regmap.backends.st.view_types import FunctionView, Member, StructView
from regmap.backends.st.views import Names
from regmap.model import Register
from regmap.records import dataclass

# Modbus function codes of the writes the poller sends.
WRITE_COIL = 0x05
WRITE_SINGLE = 0x06
WRITE_MULTIPLE = 0x10


@dataclass(frozen=True)
class WriteStruct:
    struct: StructView
    words: int  # the largest write, in words


def write_function_code(reg: Register) -> int:
    """05 for a coil, 06 for one register of one word, 16 for a pair or a wider value."""
    if reg.space == "coil":
        return WRITE_COIL
    return WRITE_SINGLE if reg.words == 1 and not reg.paired else WRITE_MULTIPLE


def write_struct(names: Names, targets: list[tuple[str, list[Register]]]) -> WriteStruct:
    words = max((regs[0].span for _, regs in targets), default=1)
    members = (
        Member("bPending", "BOOL", "a write waiting: set by F_..._WRITE_..., cleared by the poller when it sends it"),
        Member("bRefused", "BOOL", "the last F_..._WRITE_... refused its value: nothing was queued"),
        Member("bSent", "BOOL", "the poller sent the write (once; it is never sent again)"),
        Member("bDone", "BOOL", "the device confirmed the write"),
        Member("bFailed", "BOOL", "the device answered with an exception: the write did not happen"),
        Member("bOutcomeUnknown", "BOOL", "no valid reply: the device may or may not have done it; never retried"),
        Member("nFunction", "USINT", "16#05 write coil, 16#06 write one register, 16#10 write several"),
        Member("nAddr", "UINT", "the first address written"),
        Member("nCount", "UINT", "words (or coils) written"),
        Member("aWords", f"ARRAY[0..{words - 1}] OF WORD", "the encoder's words, in wire order"),
    )
    name = names.type("ST", "WRITE", what="the write request")
    return WriteStruct(StructView(name, "One setting for the poller to send, and how the last one ended.", members), words)


def queue_function(names: Names, request: WriteStruct) -> FunctionView:
    """F_<DEV>_QUEUE_WRITE: the one place a write request is filled, from an encoder's result and words."""
    name = names.function("QUEUE", "WRITE", what="the write queue")
    words = [Member(f"nWord{k}", "WORD") for k in range(request.words)]
    body = [
        f"{name} := FALSE;",
        "IF stWrite.bPending THEN",
        "    RETURN; (* one write at a time: the one waiting stays as it is *)",
        "END_IF;",
        "IF NOT bEncoded THEN",
        "    stWrite.bRefused := TRUE; (* the encoder refused the value: nothing is sent *)",
        "    RETURN;",
        "END_IF;",
        *(f"stWrite.aWords[{k}] := nWord{k};" for k in range(request.words)),
        "stWrite.nFunction := nFunction;",
        "stWrite.nAddr := nAddr;",
        "stWrite.nCount := nCount;",
        "stWrite.bRefused := FALSE;",
        "stWrite.bSent := FALSE;",
        "stWrite.bDone := FALSE;",
        "stWrite.bFailed := FALSE;",
        "stWrite.bOutcomeUnknown := FALSE;",
        "stWrite.bPending := TRUE;",
        f"{name} := TRUE;",
    ]
    inputs = (
        Member("bEncoded", "BOOL", "what the encoder returned"),
        Member("nFunction", "USINT"),
        Member("nAddr", "UINT"),
        Member("nCount", "UINT"),
        *words,
    )
    comment = "Queue a write for the poller: FALSE and bRefused when the encoder refused it, FALSE when a write is still waiting."
    return FunctionView(name, "BOOL", comment, inputs, (Member("stWrite", request.struct.type_name),), (), tuple(body))


def write_functions(
    names: Names, targets: list[tuple[str, list[Register]]], encoders: list[FunctionView], request: WriteStruct, queue: FunctionView
) -> list[FunctionView]:
    """F_<DEV>_WRITE_<X> per encoder (`targets` and `encoders` in the same order): encode, then queue."""
    return [write_function(names, label, regs, encoder, request, queue) for (label, regs), encoder in zip(targets, encoders, strict=True)]


def write_function(
    names: Names, label: str, regs: list[Register], encoder: FunctionView, request: WriteStruct, queue: FunctionView
) -> FunctionView:
    """F_<DEV>_WRITE_<X>: encode `label` (its registers `regs`) with `encoder`, then queue the words."""
    name = names.function("WRITE", label, what=f"the write request of {label}", pos=regs[0].pos)
    reg = regs[0]
    indexed = reg.array is not None and label != reg.name
    output = encoder.in_outs[0]
    encode = f"{encoder.name}({', '.join(f'{m.name} := {m.name}' for m in (*encoder.inputs, output))})"
    words = [f"aWords[{k}]" for k in range(reg.span)] if output.name == "aWords" else ["nWord"]
    words += ["16#0000"] * (request.words - len(words))
    count = 1 if reg.space == "coil" else reg.span
    inputs = list(encoder.inputs)
    body: list[str] = []
    local = [Member(output.name, output.type), Member("bEncoded", "BOOL")]
    if indexed:
        assert reg.array is not None
        inputs.append(Member("nIndex", "UINT", f"the element of {reg.array.array}"))
        local.append(Member("nAddr", "UINT"))
        body.append("CASE nIndex OF")
        body += [f"    {r.array.index if r.array else 0}: nAddr := {st_hex(r.first_address)};" for r in regs]
        body += ["ELSE", f"    {name} := FALSE;", "    stWrite.bRefused := TRUE; (* no such element *)", "    RETURN;", "END_CASE;"]
        address = "nAddr"
    else:
        address = st_hex(reg.first_address)
    args = ", ".join(
        [
            "bEncoded := bEncoded",
            f"nFunction := {st_hex(write_function_code(reg), 2)}",
            f"nAddr := {address}",
            f"nCount := {st_int(count)}",
            *(f"nWord{k} := {w}" for k, w in enumerate(words)),
            "stWrite := stWrite",
        ]
    )
    # the encoder first, on its own: the order in which a call's arguments are evaluated is the compiler's
    body += [f"bEncoded := {encode};", f"{name} := {queue.name}({args});"]
    return FunctionView(
        name,
        "BOOL",
        f"Queue a write of {label} through {encoder.name}: FALSE (bRefused, nothing queued) when the encoder refuses the value"
        + (" or the index is no element" if indexed else "")
        + ", FALSE when a write is still waiting.",
        tuple(inputs),
        (Member("stWrite", request.struct.type_name),),
        tuple(local),
        tuple(body),
    )
