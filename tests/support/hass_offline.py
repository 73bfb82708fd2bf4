"""Run Home Assistant offline: `hass`'s own entry point, without the integrations it sets up unasked.

Run with the Python of the hass tool env (tests/support/tool_envs.py), never imported by the tests:

    <hass env>/bin/python tests/support/hass_offline.py -c CONFIG_DIR

Home Assistant 2024.3 sets up `bootstrap.DEFAULT_INTEGRATIONS` (frontend, backup, network, ...) whatever
configuration.yaml says, and falls back to recovery mode -- which sets up none of the configuration --
when `frontend` fails; their requirements are not in the tool env and installing them needs the network.
This empties those two sets and then runs `homeassistant.__main__.main` with `--skip-pip`, so only what
the configuration names is set up, from what the tool env holds.
"""

from __future__ import annotations

import importlib
import sys


def main() -> int:
    # Imported by name: Home Assistant is in the hass tool env, not in regmap's.
    bootstrap = importlib.import_module("homeassistant.bootstrap")
    hass_main = importlib.import_module("homeassistant.__main__")
    bootstrap.DEFAULT_INTEGRATIONS.clear()
    bootstrap.CRITICAL_INTEGRATIONS.clear()
    sys.argv = ["hass", "--skip-pip", *sys.argv[1:]]
    return int(hass_main.main())


if __name__ == "__main__":
    raise SystemExit(main())
