"""Timestamp types as datasheets print them: `EPOCH`, `Epoch`, `UNIX time`, `timestamp`, `datetime (s since 1970)`.

Such a cell imports as `type: timestamp`. Its zone is taken only from what the table says (`UTC`, `GMT`,
`local` in the type cell or a zone column); a table that does not say leaves it out, with a note and a
reported problem: the front end then asks for it, and nobody guesses it.
"""

from __future__ import annotations

import re

# A name that is a count of seconds since 1970 by itself.
_EPOCH_NAME = re.compile(r"\b(?:epoch|unix[\s_-]*time(?:stamp)?|posix[\s_-]*time|time[\s_-]*stamp)\b", re.IGNORECASE)
# A date-and-time name, which is seconds since 1970 only when the cell says so (else it may be BCD fields).
_DATETIME_NAME = re.compile(r"\bdate[\s_/-]*time\b", re.IGNORECASE)
_SINCE_1970 = re.compile(r"1970|\bepoch\b|\bunix\b|\bs(?:ec(?:ond)?s?)?\s+since\b", re.IGNORECASE)
_UTC = re.compile(r"\b(?:utc|gmt|zulu)\b|世界时", re.IGNORECASE)
_LOCAL = re.compile(r"\blocal\b|本地", re.IGNORECASE)

ZONES = {"utc": "utc", "gmt": "utc", "z": "utc", "local": "local", "local time": "local", "本地": "local", "本地时间": "local"}
"""A zone column's cells."""


def is_time_type(text: str) -> bool:
    """Whether a type cell names seconds since 1970."""
    return bool(_EPOCH_NAME.search(text)) or (bool(_DATETIME_NAME.search(text)) and bool(_SINCE_1970.search(text)))


def printed_zone(text: str) -> str | None:
    """The zone a type cell states (`Epoch (UTC)`, `local time`), or None when it states none (or both)."""
    utc, local = bool(_UTC.search(text)), bool(_LOCAL.search(text))
    if utc == local:
        return None
    return "utc" if utc else "local"


def zone_note(printed: str) -> str:
    return (
        f"type timestamp from the printed {printed.strip()!r} (seconds since 1970); the table does not say whether they count UTC "
        "or the device's local time: zone left out, give it (utc or local) from the manual"
    )
