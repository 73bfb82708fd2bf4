"""regmap: declarative Modbus RTU register maps for motor drives, and the code generated from them."""

__version__ = "0.2.0"
