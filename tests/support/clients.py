"""The generated client modules (generated/python is on sys.path: conftest.py)."""

from __future__ import annotations

import importlib
from types import ModuleType


def client_module(device_id: str) -> ModuleType:
    return importlib.import_module(device_id)
