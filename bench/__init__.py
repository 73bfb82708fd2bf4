"""`make bench`: regmap's benchmarks, written to docs/benchmarks.md (`python -m bench`).

bus.py      bus time of read_all(), counted from the frames the simulator received
optimal.py  the read plan against a dynamic programme's minimum
genspeed.py whole-process `regmap generate` times; phases.py, the stage breakdown; synth.py, synthetic maps
overhead.py the generated client against raw pymodbus doing the same work
chelpers.py the C frame helpers: Cortex-M0 size, host ns per frame (bench/c/)
simload.py  `regmap simulate` under load beside a libmodbus server (bench/c/modbus_server.c, modbus_load.c)
report.py   the Markdown report; plot.py, its SVG plot
"""
