#!/usr/bin/env python3
"""The rooms of src/ and their floors (docs/architecture.md): a room may include only rooms on
lower floors (and its own) and public headers no higher than its floor. Fails naming each
include that runs sideways or up a floor, and each room or public header the tables here do
not know (a new one gets its floor here and in the doc); inside render/, each include that
runs up render's own sub-floors but the few listed with their reason; each row of the doc's
rooms table whose floor or "includes" column differs from the tree (--fix-doc rewrites the
column); and each source file over 800 lines but the kernel template (one body for every ISA).

Usage: check_layers.py [SRC_DIR] [--fix-doc]   (include/ and docs/ are found next to SRC_DIR)"""
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
# Public headers (include/par2d/) by the floor of what they pull in: the types and the
# functions on them (status, version, ISA levels, the scene model, the basic types of
# types.hpp, image files) sit at the bottom, so any room may use them; scene files' writer
# with scene/; the front doors (render(), Renderer, and par2d.hpp, which includes every
# header) with render/; the C API with capi/. A public header includes none above its own.
PUBLIC = {
    "status.hpp": 0, "version.hpp": 0, "isa.hpp": 0, "types.hpp": 0, "scene.hpp": 0, "image_io.hpp": 0,
    "alpha_outline.hpp": 0,
    "scene_write.hpp": 1,
    "render.hpp": 4, "renderer.hpp": 4, "par2d.hpp": 4,
    "par2d.h": 5,
}
FRONT_DOORS = {"render.hpp", "renderer.hpp", "par2d.hpp"}
# Inside render/, files on sub-floors by file name (without extension and _<arch> suffix): a
# file includes render/ files on its own sub-floor or lower, and the front doors only from
# the top one.
RENDER_FLOORS = {
    # 0: tiles and blocks, the sample pattern, the frame's counters, the pixel formats and stores,
    # ISA facts and the per-ISA kernel tables.
    "tiling": 0, "tile_plan": 0, "scene_bounds": 0, "frame_counters": 0, "frame_output": 0,
    "kernel_table": 0, "kernel_test_hooks": 0, "isa_detect": 0, "isa_usage": 0, "sample_pattern": 0,
    # 1: per-block and per-tile setup, and the tiles the scalar reference and the bounce compute.
    "kernel_shapes": 1, "model_terms": 1, "block_culling": 1, "pair_setup": 1, "tile_setup": 1,
    "cell_lists": 1, "bounce_tiles": 1, "scalar_tiles": 1,
    # 2: a frame: the light-layer cache and its tiles, the change tracker, the frame plan and its driver.
    "light_layers": 2, "layered_tiles": 2, "change_tracker": 2, "frame_plan": 2, "frame_driver": 2,
    # 3: the front door: argument checks, work estimates, render(), Renderer.
    "render_arguments": 3, "work_estimate": 3, "render": 3, "renderer": 3,
}
RENDER_FRONT = 3
# The includes inside render/ that still run up its sub-floors, each with why; one that is gone
# must leave the list too.
RENDER_BACK_ARROWS = {
    ("frame_counters.hpp", "par2d/render.hpp"): "to_frame_stats fills the public FrameStats",
    ("frame_driver.hpp", "par2d/render.hpp"): "a frame reports FrameStats and calls the host's ProgressFunction",
}
ARCH_SUFFIX = re.compile(r"_(x86|aarch64|generic|wasm)$")
LIBRARIES = {"xsimd": "xsimd", "tbb": "TBB", "stb": "stb", "nlohmann": "nlohmann/json"}
SHELLS = ("python", "tools")  # outside src/: the public API only
MAX_LINES = 800
LONG_ALLOWED = {"simd/tile_kernel.hpp"}
# Files at the top of src/ (status.cpp, status_guard.hpp) include only floor-0 public headers
# and may be included from any room.

args = [a for a in sys.argv[1:] if not a.startswith("--")]
fix_doc = "--fix-doc" in sys.argv[1:]
src = os.path.abspath(args[0] if args else os.path.join(os.path.dirname(__file__), "..", "src"))
root = os.path.dirname(src)
public_dir = os.path.join(root, "include", "par2d")
doc_path = os.path.join(root, "docs", "architecture.md")
include = re.compile(r'\s*#\s*include\s*([<"])([^>"]+)[>"]')
problems = []
render_back_arrows = 0
seen_back_arrows = set()


def includes(path):
    """(line number, quote, target) of each #include of the file."""
    with open(path, encoding="utf-8") as f:
        text = f.readlines()
    found = []
    for number, line in enumerate(text, 1):
        m = include.match(line)
        if m:
            found.append((number, m.group(1), m.group(2)))
    return text, found


def render_floor(name):
    return RENDER_FLOORS.get(ARCH_SUFFIX.sub("", os.path.splitext(name)[0]))


# Public headers: each known, none including a room or a public header above its own floor.
for name in sorted(os.listdir(public_dir)):
    if name not in PUBLIC:
        problems.append(f"include/par2d/{name}: a public header with no floor (add it to tests/check_layers.py)")
        continue
    for number, quote, target in includes(os.path.join(public_dir, name))[1]:
        head = target.split("/")[0]
        if quote == '"' and head in FLOORS:
            problems.append(f"include/par2d/{name}:{number}: a public header includes {target}")
        elif head == "par2d" and PUBLIC.get(target[6:], 99) > PUBLIC[name]:
            problems.append(f"include/par2d/{name}:{number}: includes {target} (floor {PUBLIC.get(target[6:], '?')}) "
                            f"from floor {PUBLIC[name]}")

# The rooms: what each includes (rooms, libraries, public headers) and whether it may.
uses = {}
for room in sorted(os.listdir(src)):
    path = os.path.join(src, room)
    if not os.path.isdir(path):
        for number, quote, target in includes(path)[1]:
            head = target.split("/")[0]
            if quote == '"' and (head in FLOORS or (head == "par2d" and PUBLIC.get(target[6:], 99) > 0)):
                problems.append(f"src/{room}:{number}: a file at the top of src/ includes {target} (floor-0 public headers only)")
        continue
    if room not in FLOORS:
        problems.append(f"src/{room}/: a room with no floor (add it to tests/check_layers.py and docs/architecture.md)")
        continue
    uses[room] = set()
    for name in sorted(os.listdir(path)):
        text, found = includes(os.path.join(path, name))
        if len(text) > MAX_LINES and f"{room}/{name}" not in LONG_ALLOWED:
            problems.append(f"src/{room}/{name}: {len(text)} lines (at most {MAX_LINES}: split it by concern)")
        here = render_floor(name) if room == "render" else None
        if room == "render" and here is None:
            problems.append(f"src/render/{name}: a file with no sub-floor (add it to RENDER_FLOORS in tests/check_layers.py)")
        for number, quote, target in found:
            head = target.split("/")[0]
            where = f"src/{room}/{name}:{number}"
            if quote == "<":
                if head in LIBRARIES:
                    uses[room].add(LIBRARIES[head])
                continue
            if head == "par2d":
                header = target[6:]
                uses[room].add(f"`{header}`")
                if header not in PUBLIC:
                    problems.append(f"{where}: includes {target}, a public header with no floor")
                elif PUBLIC[header] > FLOORS[room]:
                    problems.append(f"{where}: includes {target} (floor {PUBLIC[header]}) from floor {FLOORS[room]}")
                elif here is not None and header in FRONT_DOORS and here < RENDER_FRONT:
                    render_back_arrows += 1
                    seen_back_arrows.add((name, target))
                    if (name, target) not in RENDER_BACK_ARROWS:
                        problems.append(f"{where}: includes the front door {target} from render's sub-floor {here} "
                                        f"(the front door is {RENDER_FRONT}; basic types are in par2d/types.hpp)")
                continue
            if head not in FLOORS:
                continue
            if head == room:
                there = render_floor(os.path.basename(target)) if room == "render" else None
                if here is not None and there is not None and there > here:
                    render_back_arrows += 1
                    seen_back_arrows.add((name, target))
                    if (name, target) not in RENDER_BACK_ARROWS:
                        problems.append(f"{where}: includes {target} (render's sub-floor {there}) from sub-floor {here}")
                continue
            uses[room].add(head)
            if FLOORS[head] >= FLOORS[room]:
                problems.append(f"{where}: includes {head}/ (floor {FLOORS[head]}) from floor {FLOORS[room]}")
for arrow in sorted(set(RENDER_BACK_ARROWS) - seen_back_arrows):
    problems.append(f"src/render/{arrow[0]}: no longer includes {arrow[1]}: take it off RENDER_BACK_ARROWS")

# The shells outside src/ use the public API only.
for shell in SHELLS:
    for folder, _, names in os.walk(os.path.join(root, shell)):
        for name in sorted(n for n in names if n.endswith((".cpp", ".hpp", ".h"))):
            for number, quote, target in includes(os.path.join(folder, name))[1]:
                if quote == '"' and target.split("/")[0] in FLOORS:
                    rel = os.path.relpath(os.path.join(folder, name), root)
                    problems.append(f"{rel}:{number}: a shell includes {target} (the public API only)")


def column(rooms):
    """The "includes" column for these rooms: rooms, then libraries, then public headers."""
    items = set().union(*(uses[r] for r in rooms)) - set(rooms)
    ordered = (sorted(i for i in items if i in FLOORS) + sorted((i for i in items if i in LIBRARIES.values()), key=str.lower)
               + sorted(i for i in items if i.startswith("`")))
    return ", ".join(ordered) if ordered else "—"


# docs/architecture.md: every room in one row of the rooms table, on its floor, and the row's
# "includes" column what its files include.
with open(doc_path, encoding="utf-8") as f:
    doc = f.read().split("\n")
documented = set()
in_table = False
for index, line in enumerate(doc):
    if line.startswith("| floor | room"):
        in_table = True
        continue
    if not in_table:
        continue
    if not line.startswith("|"):
        break
    cells = line.strip().strip("|").split("|")
    if cells[0].strip().startswith("---"):
        continue
    if len(cells) != 4:
        problems.append(f"docs/architecture.md:{index + 1}: a rooms row without 4 columns")
        continue
    floor = cells[0].strip()
    rooms = re.findall(r"`([a-z_]+)/`", cells[1])
    ours = [r for r in rooms if r in FLOORS]
    for r in rooms:
        if r in FLOORS:
            documented.add(r)
            if floor != str(FLOORS[r]):
                problems.append(f"docs/architecture.md:{index + 1}: {r}/ on floor {floor}, tests/check_layers.py says {FLOORS[r]}")
        elif r not in SHELLS:
            problems.append(f"docs/architecture.md:{index + 1}: {r}/ is not a room of src/")
    if not ours or any(r not in uses for r in ours):
        continue
    want = column(ours)
    listed = {i.strip() for i in cells[3].split(",")} - {"—"}
    real = {i.strip() for i in want.split(",")} - {"—"}
    if listed != real:
        if fix_doc:
            cells[3] = f" {want} "
            doc[index] = "|" + "|".join(cells) + "|"
        else:
            extra = ", ".join(sorted(listed - real)) or "nothing"
            missing = ", ".join(i for i in want.split(", ") if i not in listed) or "nothing"
            problems.append(f"docs/architecture.md:{index + 1}: the includes of {', '.join(ours)} list {extra} too many "
                            f"and miss {missing} (the files include: {want}; --fix-doc writes it)")
for room in sorted(set(FLOORS) - documented):
    problems.append(f"docs/architecture.md: {room}/ is not in the rooms table")
if fix_doc:
    with open(doc_path, "w", encoding="utf-8") as f:
        f.write("\n".join(doc))

for p in problems:
    print(p)
print(f"check_layers: {len(problems)} problem(s); inside render/, {render_back_arrows} include(s) up its sub-floors "
      f"({len(RENDER_BACK_ARROWS)} allowed)")
sys.exit(1 if problems else 0)
