#!/usr/bin/env python3
"""A dense map for docs/scaling.md: about RUNS solver runs on a p x e x v0 grid, each cell solved by
cvode-bdf (rtol 1e-6) and by dem-verlet at 50 steps per contact over 4 onset phases (5 runs a
cell), the report in JSON only.
    bench/map_scene.py RUNS > map.toml"""
import sys

runs = int(float(sys.argv[1]))
cells = max(1, runs // 5)
p = [1.0, 1.25, 1.5, 2.0, 2.5]
e_count = max(1, int((cells / len(p)) ** 0.5))
v0_count = max(1, cells // (len(p) * e_count))
e = [round(0.05 + 0.9 * i / max(1, e_count - 1), 6) for i in range(e_count)]
v0 = [round(10 ** (-2 + 4 * i / max(1, v0_count - 1)), 9) for i in range(v0_count)]
print(f'''name = "map"
want = ["e", "delta_max", "tau"]
[grid]
p = {p}
e = {e}
v0 = {v0}
[[solver]]
name = "cvode-bdf"
rtol = 1e-6
[[solver]]
name = "dem-verlet"
steps_per_contact = 50
onset_phases = 4
[report]
formats = ["json"]
[limits]
max_runs = {int(runs * 1.1)}''')
