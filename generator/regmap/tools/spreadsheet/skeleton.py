"""`regmap new`: a commented skeleton map that validates, the transport block's fields explained.

The same head (device + transport) starts a draft that `regmap import` makes from a table.
Every value here that the manual must confirm says so in its comment: the skeleton validates so that
the tools work from the first minute, but its transport values are Modbus's defaults, not the device's.
"""

from __future__ import annotations

from collections.abc import Sequence

from regmap.tools.spreadsheet.yamltext import scalar


def head(
    device_id: str,
    vendor: str,
    model: str,
    *,
    made_by: str,
    function_codes: Sequence[int] = (0x03, 0x06, 0x10),
    variants: Sequence[str] = (),
) -> str:
    """The device and transport blocks; `function_codes` are those the registers' spaces need, `variants` the
    models or options the registers name (declared with their names as titles, for the manual's titles)."""
    v, m = scalar(vendor), scalar(model)
    codes = "[" + ", ".join(f"0x{c:02X}" for c in function_codes) + "]"
    declared = "".join(f"    - {{name: {name}, title: {name}}}\n" for name in variants)
    if declared:
        declared = (
            "  variants:                      # check: the models or options the table names; title each as the manual does\n" + declared
        )
    return f"""\
# {vendor} {model} register map - {made_by}.
# Fill it from the manual (docs/map-format.md). Values marked "check" are Modbus's defaults, not the
# device's: replace each with what the manual says and cite the section in `source`.
format: regmap/1
device:
  id: {device_id}                  # snake_case: prefix of generated files and C macros
  vendor: {v}
  model: {m}
  manual:
    title: {scalar(f"{vendor} {model} manual")}   # check: the manual's title as printed
    version: null                # the manual's revision, or null when it prints none
    file: {device_id}.txt             # the manual's text under ../shared/manuals/
  firmware: null                 # firmware the manual describes, or null when it names none
  map_version: 0.1.0             # semantic version of this map; 1.0.0 once it is checked against the manual
{declared}transport:
  serial:
    baud: 19200                  # check: the factory baud rate
    baud_rates: [9600, 19200]    # check: every rate the device offers (the default must be one of them)
    parity: none                 # check: none, even or odd
    data_bits: 8                 # 8 for Modbus RTU
    stop_bits: 1                 # check: 1 or 2 (Modbus: 2 stop bits when there is no parity)
  slave_ids: {{min: 1, max: 247}}  # check: the slave ids the device accepts
  broadcast_id: 0                # 0 in Modbus; null when the manual says the device ignores broadcasts
  function_codes: {codes}   # check: the function codes the manual lists
  max_read_registers: 125        # check: the manual's limit; Modbus's 125 when it is silent (say so in notes)
  max_write_registers: 123       # check: the manual's limit; Modbus's 123 when it is silent
  max_message_bytes: null        # the longest frame the manual allows, or null when not stated
  word_order: high_first         # check: order of the two words of a 32-bit value (high_first or low_first)
  crc_byte_order: low_first      # standard Modbus; a manual that says otherwise is an erratum
  undocumented_addresses: reject # reject: regmap refuses addresses the map does not list; tolerate: allows them
  bad_crc: {{reply: silent}}       # what the device does with a bad CRC (silent is the Modbus serial line rule)
  notes: Skeleton values; check every one against the manual.
"""


def skeleton(device_id: str, vendor: str, model: str) -> str:
    """The whole skeleton: head, one example register, empty examples and errata."""
    return (
        head(device_id, vendor, model, made_by="a skeleton made by `regmap new`")
        + """\
groups:
  - id: main
    title: Registers
    source: check                # the manual section of the register table
    defaults: {type: u16, access: rw}   # applied to every register of the group unless it says otherwise
    registers:
      # An example, to show the keys: replace it with the manual's registers, or fill the map from a
      # spreadsheet with `regmap import TABLE.xlsx --into THIS_FILE`.
      - name: example_register   # English snake_case, unique in the map
        param: null              # the manual's parameter id as printed (P05-02, Pr5.00), or null
        address: 0x0000          # register address
        title: Example register
        title_zh: null           # the manual's own term, verbatim
        access: r                # r, rw or w
        unit: null               # engineering unit; raw x scale = value in unit
        scale: 1
        min: null                # raw integers; null when the manual gives none
        max: null
        default: null
        source: check
        notes: An example register, not the device's.
examples: []                     # every frame the manual prints, byte for byte
errata: []                       # every contradiction in the manual: both readings, the choice, why
"""
    )
