"""`regmap import` of what users already configured: ESPHome `modbus_controller` and Home Assistant `modbus:` YAML.

reader.py reads the YAML safely (tags as data, positions kept, `${x}` substitutions resolved); esphome.py and
homeassistant.py turn entities into `Imported` registers, the inverse of backends/esphome and
backends/homeassistant; draft.py merges the registers of one device and writes the map's text.
"""
