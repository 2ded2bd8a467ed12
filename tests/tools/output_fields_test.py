#!/usr/bin/env python3
"""Output fields end to end (issue 13 part 8): dipc runs through mpiexec on 1 and 2 ranks, then

1. every .xmf is parsed as XML (xml.etree) and walked like a reader would: a temporal collection
   of steps, each a uniform grid or a spatial collection of uniform grids; every HDF DataItem must
   name a dataset of the .h5 beside it with exactly the stated dimensions and number type, every
   Topology's NumberOfElements and every Attribute's Center must match its grid's cell and node
   counts, and the listed times must be the steps' "time" attributes;
2. a box resting on a plane under gravity, friction off: implicit Euler with lumped masses gives
   sum_i m_i (v_i^{n+1} - v_i^n) / h = sum_i F_contact,i + m g exactly at the solution (the
   elastic forces cancel), so the momentum change in stats.csv must match the written contact
   forces every step; at rest the vertical contact force balances the weight; a plane pushes
   only along its normal; no friction_force is written (friction is off) and only point-plane
   pairs are counted;
3. the same box sliding with friction: the momentum change along x is the friction force, it
   opposes the motion, and while the box slides far faster than eps_v its size is mu times the
   lagged normal force (Coulomb with IPC's lagged friction: the barrier's force at the start of
   the step, i.e. the previous written step's contact force rescaled to this step's kappa);
4. contact and friction forces are the same on 1 and 2 ranks (to the rank-invariance tolerance);
5. without contact, no contact field, count or obstacle grid is written;
6. a scene with a plane, a moving OBJ obstacle and a kinematic body: body names, the kinematic
   body as its own grid (a HyperSlab of the mesh's cells) and flag, the reaction on the kinematic body's prescribed nodes (contact forces between bodies
   cancel), the obstacles' grids (the plane's patch lies in the plane and covers the scene's box;
   the obstacle's displacement is its prescribed motion); a run stopped after a checkpoint and
   restarted on the other rank count has the uninterrupted run's fields and obstacle data.

Usage: output_fields_test.py --dipc build/src/app/dipc --mpiexec "mpiexec --oversubscribe" --work DIR
"""
import argparse
import csv
import os
import shlex
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

G = 9.81
RHO, SIZE = 1000.0, 0.1
MASS = RHO * SIZE ** 3  # lumped masses sum to the box's mass
DT = 0.01
TIGHT = ["-dipc_velocity_tol", "1e-9", "-ksp_rtol", "1e-12", "-ksp_max_it", "5000"]


def box_scene(steps, friction=0.0, velocity=(0, 0, 0), extra_bodies="", extra_contact="", gravity=True):
    body = ('{"name": "box", "box": {"size": [%g, %g, %g], "resolution": [2, 2, 2], "origin": [0, 0, 0.0005]}, '
            '"initial_velocity": [%g, %g, %g]}' % (SIZE, SIZE, SIZE, *velocity))
    return """{
  "materials": [{"name": "rubber", "E": 1e5, "nu": 0.3, "rho": %g}],
  "geometry": [%s%s],
  "boundary_conditions": {"gravity": [0, 0, %g]},
  "time": {"integrator": "implicit_euler", "dt": %g, "steps": %d},
  "contact": {"enabled": true, "dhat": 1e-3, "dhat_relative": false, "friction": %g, "epsv": 1e-3,
              "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]%s}
}
""" % (RHO, body, extra_bodies, -G if gravity else 0.0, DT, steps, friction, extra_contact)


def run(args, scene, ranks, out, extra=()):
    command = (shlex.split(args.mpiexec) + ["-n", str(ranks), args.dipc, scene, "-dipc_quiet", "-dipc_output", out]
               + TIGHT + list(extra))
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    if result.returncode != 0:
        sys.exit("FAIL: %s exited %d:\n%s" % (" ".join(command), result.returncode, result.stdout[-3000:]))


NUMBER_TYPES = {("Float", "8"): ("f", 8), ("Int", "8"): ("i", 8), ("Int", "4"): ("i", 4)}


def check_data_item(item, h5, h5_name, what):
    """The array an XDMF DataItem stands for: an HDF dataset of the .h5 beside the .xmf with the
    stated dimensions and type, or a HyperSlab (start, stride and count per dimension) of one."""
    if item.get("ItemType") == "HyperSlab":
        selection, source = item.findall("DataItem")
        assert selection.get("Format") == "XML", what + ": HyperSlab selection is not XML"
        rank = int(selection.get("Dimensions").split()[1])
        numbers = [int(v) for v in selection.text.split()]
        start, stride, count = numbers[:rank], numbers[rank:2 * rank], numbers[2 * rank:]
        whole = check_data_item(source, h5, h5_name, what)
        assert whole.ndim == rank, what + ": HyperSlab rank"
        assert tuple(count) == tuple(int(d) for d in item.get("Dimensions").split()), what + ": HyperSlab count"
        assert all(s >= 0 and t >= 1 and c >= 1 and s + (c - 1) * t < n
                   for s, t, c, n in zip(start, stride, count, whole.shape)), what + ": HyperSlab outside its dataset"
        return whole[tuple(slice(s, s + c * t, t) for s, t, c in zip(start, stride, count))]
    assert item.get("Format") == "HDF", what + ": not an HDF DataItem"
    file_name, _, path = item.text.strip().partition(":")
    assert file_name == h5_name, "%s: refers to %s, not %s" % (what, file_name, h5_name)
    assert path in h5, "%s: no dataset %s in %s" % (what, path, h5_name)
    dataset = h5[path]
    stated = tuple(int(d) for d in item.get("Dimensions").split())
    assert dataset.shape == stated, "%s: %s has shape %s, the .xmf states %s" % (what, path, dataset.shape, stated)
    kind, size = NUMBER_TYPES[(item.get("NumberType"), item.get("Precision"))]
    assert dataset.dtype.kind == kind and dataset.dtype.itemsize == size, \
        "%s: %s is %s, the .xmf states %s%d" % (what, path, dataset.dtype, kind, size)
    return dataset[...]


def check_uniform_grid(grid, h5, h5_name, step_name):
    what = "%s/%s" % (step_name, grid.get("Name"))
    topology, geometry = grid.find("Topology"), grid.find("Geometry")
    assert topology is not None and geometry is not None, what + ": no Topology or Geometry"
    cells = check_data_item(topology.find("DataItem"), h5, h5_name, what + " topology")
    assert int(topology.get("NumberOfElements")) == cells.shape[0], what + ": NumberOfElements"
    per_cell = {"Hexahedron": 8, "Quadrilateral": 4, "Triangle": 3}[topology.get("TopologyType")]
    assert cells.shape[1] == per_cell, what + ": nodes per cell"
    points = check_data_item(geometry.find("DataItem"), h5, h5_name, what + " geometry")
    assert geometry.get("GeometryType") == "XYZ" and points.shape[1] == 3
    ids = cells[...]
    assert ids.min() >= 0 and ids.max() < points.shape[0], what + ": topology names nodes that do not exist"
    names, body = set(), None
    for attribute in grid.findall("Attribute"):
        name = attribute.get("Name")
        assert name not in names, what + ": attribute %s twice" % name
        names.add(name)
        data = check_data_item(attribute.find("DataItem"), h5, h5_name, what + " " + name)
        rows = points.shape[0] if attribute.get("Center") == "Node" else cells.shape[0]
        assert data.shape[0] == rows, "%s: attribute %s has %d rows for %d" % (what, name, data.shape[0], rows)
        columns = 3 if attribute.get("AttributeType") == "Vector" else 1
        assert (data.shape[1] if data.ndim == 2 else 1) == columns, what + ": attribute %s columns" % name
        if name == "body":
            body = data
    return names, body


def check_xdmf(out, with_bodies=False):
    """Parses out/dipc.xmf; returns, per step, the grids' names and their attributes (and, with
    with_bodies, per step each bodies' grid's cell field "body")."""
    xmf, h5_path = os.path.join(out, "dipc.xmf"), os.path.join(out, "dipc.h5")
    root = ET.parse(xmf).getroot()
    assert root.tag == "Xdmf"
    series = root.find("Domain/Grid")
    assert series.get("GridType") == "Collection" and series.get("CollectionType") == "Temporal"
    steps, bodies = [], []
    with h5py.File(h5_path, "r") as h5:
        for k, step in enumerate(series.findall("Grid")):
            time = float(step.find("Time").get("Value"))
            assert time == h5["steps/%d" % k].attrs["time"], "step %d: time" % k
            if step.get("GridType") == "Uniform":
                grids = [step]
            else:
                assert step.get("GridType") == "Collection" and step.get("CollectionType") == "Spatial"
                grids = step.findall("Grid")
            checked = {g.get("Name"): check_uniform_grid(g, h5, "dipc.h5", step.get("Name")) for g in grids}
            hexahedra = [g for g in grids if g.find("Topology").get("TopologyType") == "Hexahedron"]
            assert sum(int(g.find("Topology").get("NumberOfElements")) for g in hexahedra) == len(h5["mesh/topology"]), \
                "step %d: the bodies' grids do not hold every element once" % k
            steps.append({name: names for name, (names, _) in checked.items()})
            bodies.append({name: body for name, (_, body) in checked.items() if body is not None})
        assert len(steps) == len(h5["steps"]), "the .xmf lists %d steps, the .h5 holds %d" % (len(steps), len(h5["steps"]))
    return (steps, bodies) if with_bodies else steps


def stats(out):
    with open(os.path.join(out, "stats.csv")) as f:
        return list(csv.DictReader(f))


def read_forces(out):
    with h5py.File(os.path.join(out, "dipc.h5"), "r") as h5:
        n = len(h5["steps"])
        fc = [h5["steps/%d/contact_force" % k][...] for k in range(n)]
        ff = [h5["steps/%d/friction_force" % k][...] for k in range(n)] if "friction_force" in h5["steps/0"] else None
        pairs = [{a[len("contact_pairs_"):]: int(v) for a, v in h5["steps/%d" % k].attrs.items()
                  if a.startswith("contact_pairs_")} for k in range(n)]
    return fc, ff, pairs


def momentum_balance(out, component, force, p0=0.0):
    """max over steps of |dp/h - (sum of the force + m g)| / (m g); p0 the initial momentum."""
    rows = stats(out)
    p_prev, worst = p0, 0.0
    for k, row in enumerate(rows, start=1):
        p = float(row["momentum_" + "xyz"[component]])
        expected = force[k][:, component].sum() + (-MASS * G if component == 2 else 0.0)
        worst = max(worst, abs((p - p_prev) / float(row["dt"]) - expected) / (MASS * G))
        p_prev = p
    return worst


def rank_difference(a, b):
    scale = max(np.abs(x).max() for x in a)
    return max(np.abs(x - y).max() for x, y in zip(a, b)) / scale


def resting_box(args, work):
    scene = os.path.join(work, "rest.json")
    with open(scene, "w") as f:
        f.write(box_scene(40))
    outs = {r: os.path.join(work, "rest_np%d" % r) for r in (1, 2)}
    for r, out in outs.items():
        run(args, scene, r, out)
    for out in outs.values():
        grids = check_xdmf(out)
        assert set(grids[0]) == {"bodies", "plane0"}, grids[0]
        assert "contact_force" in grids[-1]["bodies"] and "friction_force" not in grids[-1]["bodies"]
    fc, ff, pairs = read_forces(outs[1])
    assert ff is None, "friction_force written with friction off"
    assert all(p["point_plane"] > 0 for p in pairs[1:]) and all(
        n == 0 for p in pairs for kind, n in p.items() if kind != "point_plane"), pairs[-1]
    balance = momentum_balance(outs[1], 2, fc)
    total = fc[-1].sum(axis=0)
    vz = abs(float(stats(outs[1])[-1]["momentum_z"])) / MASS
    print("rest: sum F_contact = %s N, weight %.6f N, |v_z| %.2e m/s, momentum balance %.2e m g"
          % (np.array2string(total, precision=6), MASS * G, vz, balance))
    assert balance < 1e-5, "momentum change and contact force disagree: %.3e m g" % balance
    assert abs(total[2] - MASS * G) < 1e-3 * MASS * G, "at rest the contact force does not balance the weight"
    assert max(np.abs(f[:, :2]).max() for f in fc) < 1e-12, "a plane pushed along its surface"
    difference = rank_difference(fc, read_forces(outs[2])[0])
    print("rest: contact force, 2 ranks vs 1: %.2e of the largest nodal force" % difference)
    assert difference < 1e-6


def sliding_box(args, work):
    mu = 0.4
    scene = os.path.join(work, "slide.json")
    with open(scene, "w") as f:
        f.write(box_scene(12, friction=mu, velocity=(0.5, 0, 0)))
    outs = {r: os.path.join(work, "slide_np%d" % r) for r in (1, 2)}
    for r, out in outs.items():
        run(args, scene, r, out)
    for out in outs.values():
        assert "friction_force" in check_xdmf(out)[-1]["bodies"]
    fc, ff, _ = read_forces(outs[1])
    balance = momentum_balance(outs[1], 0, ff, MASS * 0.5)
    rows = stats(outs[1])
    checked = 0
    for k, row in enumerate(rows, start=1):
        vx = float(row["momentum_x"]) / MASS
        fx = ff[k][:, 0].sum()
        if k >= 2 and vx > 100 * 1e-3:  # sliding far faster than eps_v: every pair slides
            # Lagged friction (IPC §5): step k's normal forces are the barrier's at the start of
            # the step (the end of step k-1, written there) with step k's stiffness kappa_k.
            normal = fc[k - 1][:, 2].sum() * float(row["kappa"]) / float(rows[k - 2]["kappa"])
            assert fx < 0, "step %d: friction does not oppose the motion" % k
            assert abs(abs(fx) / normal - mu) < 1e-3 * mu, "step %d: |F_f| / F_n = %.5f, mu %.2f" % (k, abs(fx) / normal, mu)
            checked += 1
    print("slide: momentum balance along x %.2e m g, Coulomb checked on %d sliding steps, last |F_f|/F_n %.4f"
          % (balance, checked, abs(ff[-1][:, 0].sum()) / fc[-1][:, 2].sum()))
    assert checked >= 3, "the box stopped too early: Coulomb's law not checked"
    assert balance < 1e-5
    fc2, ff2, _ = read_forces(outs[2])
    difference = max(rank_difference(fc, fc2), rank_difference(ff, ff2))
    print("slide: contact and friction forces, 2 ranks vs 1: %.2e" % difference)
    assert difference < 1e-6


OBJ = "# a 0.2 x 0.2 square at z = 0 (two triangles)\nv 0 0 0\nv 0.2 0 0\nv 0.2 0.2 0\nv 0 0.2 0\nf 1 2 3\nf 1 3 4\n"


def scene_features(args, work):
    with open(os.path.join(work, "lift.obj"), "w") as f:
        f.write(OBJ)
    # The pusher starts 2 mm from the box's +x face and pushes it along -x.
    pusher = (', {"name": "pusher", "box": {"size": [0.05, 0.05, 0.05], "resolution": [1, 1, 1], '
              '"origin": [0.102, 0.025, 0.02]}, "kinematic": {"type": "velocity", "velocity": [-0.2, 0, 0]}}')
    lift = (', "obstacles": [{"name": "lift", "mesh": "lift.obj", "translation": [0.6, 0, -0.1], '
            '"motion": {"type": "velocity", "velocity": [0, 0, 0.5]}}]')
    scene = os.path.join(work, "features.json")
    with open(scene, "w") as f:
        f.write(box_scene(8, friction=0.2, extra_bodies=pusher, extra_contact=lift))
    whole, restarted = os.path.join(work, "features_whole"), os.path.join(work, "features_restart")
    run(args, scene, 1, whole)
    run(args, scene, 2, restarted, ["-dipc_steps", "4", "-dipc_checkpoint_every", "4"])
    run(args, scene, 1, restarted, ["-dipc_restart", "auto"])
    for out in (whole, restarted):
        # The kinematic pusher is its own grid (ParaView block), next to the box and the obstacles.
        grids, bodies = check_xdmf(out, with_bodies=True)
        assert list(grids[0]) == ["box", "pusher", "plane0", "lift"], list(grids[0])
        for name in ("box", "pusher"):
            assert {"contact_force", "friction_force", "kinematic", "body"} <= grids[-1][name]
        assert (bodies[-1]["box"] == 0).all() and (bodies[-1]["pusher"] == 1).all(), "a grid holds another body's cells"
    with h5py.File(os.path.join(whole, "dipc.h5"), "r") as a, h5py.File(os.path.join(restarted, "dipc.h5"), "r") as b:
        assert [n.decode() for n in a["mesh/body_names"][...]] == ["box", "pusher"]
        kinematic, body = a["mesh/kinematic"][...], a["mesh/body"][...]
        assert np.array_equal(kinematic, (body == 1).astype(kinematic.dtype)), "kinematic flag is not the pusher's"
        # The pusher's (prescribed) nodes carry the box's reaction: body-body pairs act and react,
        # the plane pushes along z only, so the x components of all contact forces cancel.
        pusher_nodes = np.unique(a["mesh/topology"][...][body == 1])
        last = len(a["steps"]) - 1
        fc = a["steps/%d/contact_force" % last][...]
        push = fc[pusher_nodes, 0].sum()  # the box pushes back along +x
        pairs = dict(a["steps/%d" % last].attrs)
        print("features: the box pushes back on the pusher with %.4f N along +x (%d point-triangle, %d edge-edge pairs); "
              "sum of all contact forces along x %.2e N" % (push, pairs["contact_pairs_point_triangle"],
                                                         pairs["contact_pairs_edge_edge"], fc[:, 0].sum()))
        assert push > 0.1 and pairs["contact_pairs_point_triangle"] > 0, "the pusher did not reach the box"
        assert abs(fc[:, 0].sum()) < 1e-9 * push, "contact forces between bodies do not cancel"
        assert a["obstacles/0"].attrs["kind"].decode() == "plane" and a["obstacles/1"].attrs["name"].decode() == "lift"
        # The plane's patch: in the plane z = 0, covering the box of the bodies and the obstacle.
        corners = a["obstacles/0/coordinates"][...]
        X = np.vstack([a["mesh/coordinates"][...], a["obstacles/1/coordinates"][...]])
        assert np.abs(corners[:, 2]).max() < 1e-12
        assert (corners[:, :2].min(axis=0) < X[:, :2].min(axis=0)).all() and \
            (corners[:, :2].max(axis=0) > X[:, :2].max(axis=0)).all(), "the plane patch does not cover the scene"
        for k in range(len(a["steps"])):
            t = a["steps/%d" % k].attrs["time"]
            u = a["steps/%d/obstacles/1/displacement" % k][...]
            assert np.allclose(u, np.tile([0, 0, 0.5 * t], (len(u), 1)), rtol=0, atol=1e-15), "step %d: lift motion" % k
        assert "1" not in a.get("steps/0/obstacles", {}) or "0" not in a["steps/0/obstacles"], "the plane moved"
        # The restarted run (2 ranks to step 4, then 1 rank) has the uninterrupted run's fields.
        assert len(a["steps"]) == len(b["steps"])
        worst = 0.0
        for k in range(len(a["steps"])):
            for name in ("contact_force", "friction_force", "displacement"):
                x, y = a["steps/%d/%s" % (k, name)][...], b["steps/%d/%s" % (k, name)][...]
                worst = max(worst, np.abs(x - y).max() / max(1e-30, np.abs(x).max()))
            assert np.array_equal(a["steps/%d/obstacles/1/displacement" % k][...],
                                  b["steps/%d/obstacles/1/displacement" % k][...])
            assert dict(a["steps/%d" % k].attrs) == dict(b["steps/%d" % k].attrs), "step %d: pair counts" % k
        print("features: restarted (2 ranks, then 1) vs uninterrupted: fields differ by %.2e (relative)" % worst)
        assert worst < 1e-6


def no_contact(args, work):
    """Without contact nothing of it is computed or written: the .xmf stays one grid per step."""
    scene = os.path.join(work, "free.json")
    with open(scene, "w") as f:
        f.write(box_scene(2).replace('"enabled": true', '"enabled": false'))
    out = os.path.join(work, "free")
    run(args, scene, 2, out)
    grids = check_xdmf(out)
    assert all(list(g) == ["step_%d" % k] for k, g in enumerate(grids)), grids[0]
    assert not {"contact_force", "friction_force", "kinematic"} & grids[-1]["step_%d" % (len(grids) - 1)]
    with h5py.File(os.path.join(out, "dipc.h5"), "r") as h5:
        assert "obstacles" not in h5 or len(h5["obstacles"]) == 0
        assert not any(a.startswith("contact_pairs") for a in h5["steps/1"].attrs)
        assert [n.decode() for n in h5["mesh/body_names"][...]] == ["box"]
    assert "contact_pairs" not in stats(out)[0]
    print("no contact: no contact fields, counts or obstacle grids")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dipc", required=True)
    parser.add_argument("--mpiexec", default="mpiexec")
    parser.add_argument("--work", required=True)
    args = parser.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    resting_box(args, args.work)
    sliding_box(args, args.work)
    scene_features(args, args.work)
    no_contact(args, args.work)
    print("PASS")


if __name__ == "__main__":
    main()
