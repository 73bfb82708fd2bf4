"""The layer below both wings: what back ends and field tools share.

`text` (numbers, engineering values, titles, articles), `decoding` (words -> named values) and
`contract` (the model as JSON). It imports the model and the runtime, never `regmap.backends` or
`regmap.tools` (tests/project/test_layers.py checks it).
"""
