#!/usr/bin/env python3
"""Checks docs/design.md's layer table (section 2) against the CMake targets of src/.

The rooms of src/ are libraries; what each room links (target_link_libraries of its targets in
src/**/CMakeLists.txt) is the code's layer graph. The table in design.md lists the rooms from
the bottom up, one row each, with the rooms it uses in the "uses" column. This fails when

  - the table names a use that no target of the room links, or misses one that a target links
    (uses between dipc's own rooms only: external libraries are not compared);
  - a room uses a room of a later row (an arrow pointing up), or a room is missing from the table.

Rooms are the folders of src/ with a CMakeLists.txt; contact/'s concern folders (geometry/, ccd/,
friction/, broad_phase/) are part of contact, and contact/distributed/ is a room of its own.

Usage: check_layers.py [--print] [--png FILE] [--design FILE]
  --print   print the rooms and their uses as CMake has them
  --png     draw the graph from the CMake files (needs matplotlib)
  --design  check this copy of design.md instead (the checker's own test)
Exit status 1 on a mismatch.
"""
import glob
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DESIGN = os.path.join(ROOT, "docs", "design.md")
CONTACT_CONCERNS = ("geometry", "ccd", "friction", "broad_phase")


def room_of(cmake_file):
    folder = os.path.relpath(os.path.dirname(cmake_file), os.path.join(ROOT, "src")).replace(os.sep, "/")
    parts = folder.split("/")
    if parts[0] == "contact" and len(parts) > 1 and parts[1] in CONTACT_CONCERNS:
        return "contact"
    return folder


def commands(text, name):
    """The argument lists of every `name(...)` call in a CMake file, comments removed."""
    text = re.sub(r"#[^\n]*", "", text)
    return [m.group(1).split() for m in re.finditer(r"\b" + name + r"\s*\(([^)]*)\)", text)]


def cmake_graph():
    """{room: set of rooms it links}, from src/*/**/CMakeLists.txt."""
    owner, links = {}, []
    for path in glob.glob(os.path.join(ROOT, "src", "*", "**", "CMakeLists.txt"), recursive=True):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        room = room_of(path)
        for kind in ("add_library", "add_executable", "dipc_device_library"):
            for args in commands(text, kind):
                owner[args[0]] = room
        for args in commands(text, "target_link_libraries"):
            links.append((room, args[1:]))
    graph = {room: set() for room in owner.values()}
    for room, targets in links:
        for target in targets:
            used = owner.get(target)
            if used and used != room:
                graph[room].add(used)
    return graph


def documented_graph(design):
    """[(room, set of rooms it uses)] in the order of design.md's layer table."""
    with open(design, encoding="utf-8") as f:
        lines = f.read().splitlines()
    header = next(i for i, line in enumerate(lines) if re.match(r"\|\s*room\s*\|.*\|\s*uses\s*\|", line))
    columns = [c.strip() for c in lines[header].strip("|").split("|")]
    uses_column = columns.index("uses")
    rows = []
    for line in lines[header + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip("|").split("|")]
        room = re.fullmatch(r"`src/(.+)/`", cells[0]).group(1)
        uses = re.sub(r"\([^)]*\)", "", cells[uses_column])  # notes in parentheses
        rows.append((room, {u.strip() for u in uses.split(",") if u.strip() not in ("", "—")}))
    return rows


def check(graph, rows):
    problems = []
    order = [room for room, _ in rows]
    for room in sorted(set(graph) - set(order)):
        problems.append(f"src/{room}/ (a room of the CMake files) has no row in the layer table")
    for position, (room, uses) in enumerate(rows):
        if room not in graph:
            problems.append(f"src/{room}/ (layer table) defines no target in src/{room}/CMakeLists.txt")
            continue
        for used in sorted(uses - graph[room]):
            problems.append(f"layer table: {room} uses {used}, but no target of src/{room}/ links one of src/{used}/")
        for used in sorted(graph[room] - uses):
            problems.append(f"layer table: {room} does not list {used}, which src/{room}/ links")
        for used in sorted(graph[room] | uses):
            if used in order and order.index(used) > position:
                problems.append(f"layer table: {room} uses {used}, which is above it (an arrow pointing up)")
    return problems


def draw(graph, order, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # Level: the longest chain of uses below a room; rooms of one level side by side.
    level = {}

    def level_of(room):
        if room not in level:
            level[room] = 1 + max((level_of(u) for u in graph[room]), default=-1)
        return level[room]

    for room in graph:
        level_of(room)
    # Only the arrows that no longer path implies (the transitive reduction): the picture shows
    # the layering, --print and the table every use.
    def below(room):
        seen, todo = set(), list(graph[room])
        while todo:
            r = todo.pop()
            if r not in seen:
                seen.add(r)
                todo += graph[r]
        return seen

    arrows = {room: {u for u in uses if not any(u in below(v) for v in uses if v != u)}
              for room, uses in graph.items()}
    by_level = {}
    for room in order:
        by_level.setdefault(level[room], []).append(room)
    # Within a level, rooms under the middle of their users, top down, so arrows cross less.
    x_of = {}
    for lv in sorted(by_level, reverse=True):
        users = {r: [x_of[u] for u in graph if r in arrows[u] and u in x_of] for r in by_level[lv]}
        by_level[lv].sort(key=lambda r: sum(users[r]) / len(users[r]) if users[r] else 1e9)
        for i, r in enumerate(by_level[lv]):
            x_of[r] = (i + 0.5) / len(by_level[lv])
    width = max(len(rooms) for rooms in by_level.values())
    position = {}
    for lv, rooms in by_level.items():
        for i, room in enumerate(rooms):
            position[room] = ((i + 0.5) * width / len(rooms), lv)
    fig, ax = plt.subplots(figsize=(2.0 * width + 1, 1.1 * len(by_level) + 1))
    for room, uses in arrows.items():
        for used in uses:
            (x0, y0), (x1, y1) = position[room], position[used]
            # Arrows over more than one level bend, so that they do not run through the rooms between.
            bend = 0.0 if y0 - y1 == 1 else 0.25
            ax.annotate("", xy=(x1, y1 + 0.18), xytext=(x0, y0 - 0.18),
                        arrowprops=dict(arrowstyle="->", color="0.45", lw=0.9, shrinkA=0, shrinkB=0,
                                        connectionstyle=f"arc3,rad={bend}"))
    for room, (x, y) in position.items():
        ax.text(x, y, room, ha="center", va="center", fontsize=10,
                bbox=dict(boxstyle="round,pad=0.35", fc="#e8eef7", ec="#40618f"))
    ax.set_xlim(-0.2, width + 0.2)
    ax.set_ylim(-0.6, max(by_level) + 0.6)
    ax.axis("off")
    ax.set_title("dipc: rooms of src/ and what each links (src/**/CMakeLists.txt; arrows implied by others omitted)",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main(argv):
    graph = cmake_graph()
    rows = documented_graph(argv[argv.index("--design") + 1] if "--design" in argv else DESIGN)
    if "--print" in argv:
        for room in [r for r, _ in rows if r in graph] + sorted(set(graph) - {r for r, _ in rows}):
            print(f"{room}: {', '.join(sorted(graph[room])) or '—'}")
    if "--png" in argv:
        order = [r for r, _ in rows if r in graph] + sorted(set(graph) - {r for r, _ in rows})
        draw(graph, order, argv[argv.index("--png") + 1])
    problems = check(graph, rows)
    for p in problems:
        print(p)
    print(f"{len(rows)} rooms in the layer table, {sum(len(u) for u in graph.values())} uses in the CMake files, "
          f"{len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
