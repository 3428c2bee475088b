#!/usr/bin/env python3
"""The rooms of src/ and their floors (docs/architecture.md): a room may include only rooms on
lower floors (and its own). Fails naming each include that runs sideways or up a floor, and
each room the table does not know (a new room gets its floor here and in the doc); and each
source file over 800 lines but the kernel template (one body for every ISA)."""
import os
import re
import sys

FLOORS = {
    "geometry": 0, "lighting": 0, "io": 0, "parallel": 0,
    "scene": 1,
    "world": 2,
    "culling": 3, "scalar": 3, "raycast": 3, "simd": 3,
    "render": 4,
    "capi": 5,
}
MAX_LINES = 800
LONG_ALLOWED = {"simd/tile_kernel.hpp"}
# Files at the top of src/ (status.cpp, status_guard.hpp) include only the public headers
# and may be included from any room.

src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "src")
include = re.compile(r'#\s*include\s+"([A-Za-z0-9_]+)/')
problems = []
for room in sorted(os.listdir(src)):
    path = os.path.join(src, room)
    if not os.path.isdir(path):
        continue
    if room not in FLOORS:
        problems.append(f"src/{room}/: a room with no floor (add it to tests/check_layers.py and docs/architecture.md)")
        continue
    for name in sorted(os.listdir(path)):
        with open(os.path.join(path, name), encoding="utf-8") as f:
            text = f.readlines()
        if len(text) > MAX_LINES and f"{room}/{name}" not in LONG_ALLOWED:
            problems.append(f"src/{room}/{name}: {len(text)} lines (at most {MAX_LINES}: split it by concern)")
        for number, line in enumerate(text, 1):
            m = include.match(line)
            if not m or m.group(1) in ("par2d", room) or m.group(1) not in FLOORS:
                continue
            target = m.group(1)
            if FLOORS[target] >= FLOORS[room]:
                problems.append(f"src/{room}/{name}:{number}: includes {target}/ (floor {FLOORS[target]}) "
                                f"from floor {FLOORS[room]}")
for p in problems:
    print(p)
print(f"check_layers: {len(problems)} problem(s)")
sys.exit(1 if problems else 0)
