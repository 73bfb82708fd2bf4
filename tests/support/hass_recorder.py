"""What a running Home Assistant recorded: the latest state of each entity, read from its recorder database."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

QUERY = (
    "SELECT m.entity_id, s.state, a.shared_attrs FROM states s JOIN states_meta m ON s.metadata_id = m.metadata_id"
    " LEFT JOIN state_attributes a ON s.attributes_id = a.attributes_id ORDER BY s.state_id"
)


def recorded_states(db: Path) -> dict[str, tuple[str, str, dict[str, object]]]:
    """friendly_name -> (entity id, latest state, its attributes); empty while the recorder makes its schema."""
    if not db.exists():
        return {}
    try:
        with sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=5) as con:
            rows = con.execute(QUERY).fetchall()
    except sqlite3.OperationalError:
        return {}  # the schema is still being created
    out: dict[str, tuple[str, str, dict[str, object]]] = {}
    for entity_id, state, attrs in rows:
        attributes = json.loads(attrs) if attrs else {}
        name = attributes.get("friendly_name")
        if name is not None and state is not None:
            out[str(name)] = (str(entity_id), str(state), attributes)
    return out
