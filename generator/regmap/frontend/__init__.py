"""The front end: YAML -> JSON Schema -> semantic checks -> one frozen `Device` model."""

from regmap.frontend.load import load_map, load_map_text

__all__ = ["load_map", "load_map_text"]
