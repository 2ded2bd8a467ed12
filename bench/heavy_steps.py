#!/usr/bin/env python3
"""Newton iterations per step of a contact-family member, and how they change when its friction
changes (issue 29, item 4: why the steps where many surfaces meet take many Newton iterations).

  bench/heavy_steps.py --dipc build/src/app/dipc [--member stack] [--elements 8000 | --refine R]
      [--steps 6] [--ranks 1] [--variants default,no_friction,epsv_x10,epsv_x0.1]
      [--out bench/results] [--tag TAG] [-- extra dipc options]

Each variant is the member's scene (bench/contact_family/<member>.json, scaled as
contact_family.py scales it) with one change:
  default            the scene as shipped
  no_friction        contact.friction 0 (no friction form)
  epsv_xK            contact.epsv times K (the friction's smoothing speed; K a number)
  friction_iterations_N   contact.friction_iterations N (lag updates per step)
  -OPTION=VALUE      the shipped scene run with the dipc option -OPTION VALUE (-OPTION alone: a flag),
                     e.g. -dipc_friction_majorize_reversals=0
Prints one table (steps down, variants across: Newton iterations and the smallest line-search
step α of the step) and writes <out>/heavy_steps_<tag>.csv with a row per variant and step:
variant, member, elements, ranks, step, newton, ksp, alpha_min, alpha_ccd, contacts, step_s,
status. A variant that fails keeps the steps it finished and names its exit status; the exit
status is 1 when a variant failed or printed fewer step lines than --steps.
"""
import argparse
import csv
import json
import os
import re
import sys
import tempfile

from contact_family import SCENES, member_scene
from run_dipc import run_dipc

STEP_LINE = re.compile(r"^step\s+(\d+)\s.*?newton\s+(\d+).*?ksp\s+(\d+)\s+alpha_min\s+(\S+).*?\s([0-9.]+) s"
                       r"(?:\s*\|\s*contacts\s+(\d+).*?alpha_ccd\s+(\S+))?", re.M)
FIELDS = ["variant", "member", "elements", "ranks", "step", "newton", "ksp", "alpha_min", "alpha_ccd", "contacts",
          "step_s", "status"]


def apply_variant(scene, variant):
    """The scene with the variant's change; ValueError names a variant this script does not know."""
    contact = scene.setdefault("contact", {})
    if variant == "default" or variant.startswith("-"):
        pass
    elif variant == "no_friction":
        contact["friction"] = 0.0
    elif variant.startswith("epsv_x"):
        contact["epsv"] = contact.get("epsv", 1e-3) * float(variant[len("epsv_x"):])
    elif variant.startswith("friction_iterations_"):
        contact["friction_iterations"] = int(variant[len("friction_iterations_"):])
    else:
        raise ValueError("unknown variant %r (default, no_friction, epsv_xK, friction_iterations_N, -OPTION=VALUE)"
                         % variant)
    return scene


def variant_scene(args, variant, workdir):
    """The path of the variant's scene file: the member scaled to --elements (or as shipped, for
    --refine), then changed."""
    scene = member_scene(args.member, args.elements)
    out = os.path.join(workdir, "%s_%s.json" % (args.member, re.sub(r"[^A-Za-z0-9_.]", "_", variant)))
    with open(out, "w") as f:
        json.dump(apply_variant(scene, variant), f, indent=1)
    return out


def run_variant(args, variant, workdir):
    scene = variant_scene(args, variant, workdir)
    options = ["-dipc_steps", args.steps, "-dipc_no_output"] + (["-dipc_refine", args.refine] if args.refine else [])
    if variant.startswith("-"):
        options += variant.split("=", 1)
    text, status, _ = run_dipc(args.dipc, args.ranks, [scene] + options + args.extra, timeout=args.timeout)
    elements = re.search(r"elements (\d+)", text)
    rows = []
    for m in STEP_LINE.finditer(text):
        rows.append({"variant": variant, "member": args.member, "elements": elements.group(1) if elements else "",
                     "ranks": args.ranks, "step": int(m.group(1)), "newton": int(m.group(2)), "ksp": int(m.group(3)),
                     "alpha_min": float(m.group(4)), "alpha_ccd": m.group(7) or "", "contacts": m.group(6) or "",
                     "step_s": float(m.group(5)), "status": status})
    if status != 0:
        tail = "\n".join(text.strip().splitlines()[-5:])
        print("variant %s: exit %s after %d steps\n%s" % (variant, status, len(rows), tail), file=sys.stderr)
    return rows


def print_table(rows, variants):
    steps = sorted({r["step"] for r in rows})
    cell = {(r["variant"], r["step"]): "%d (α %.3g)" % (r["newton"], r["alpha_min"]) for r in rows}
    width = max([len(v) for v in variants] + [14])
    print("step  " + "  ".join(v.rjust(width) for v in variants))
    for s in steps:
        print("%4d  " % s + "  ".join(cell.get((v, s), "-").rjust(width) for v in variants))
    totals = ["%d" % sum(r["newton"] for r in rows if r["variant"] == v) for v in variants]
    heaviest = ["%d" % max([r["newton"] for r in rows if r["variant"] == v] or [0]) for v in variants]
    print("all   " + "  ".join(t.rjust(width) for t in totals))
    print("max   " + "  ".join(t.rjust(width) for t in heaviest))


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--dipc", required=True)
    p.add_argument("--member", default="stack", help="a scene of bench/contact_family")
    size = p.add_mutually_exclusive_group()
    size.add_argument("--elements", type=int, help="scale every box towards this many hexes in all")
    size.add_argument("--refine", help="-dipc_refine level of the shipped scene")
    p.add_argument("--steps", default="6")
    p.add_argument("--ranks", type=int, default=1)
    p.add_argument("--variants", default="default,no_friction,epsv_x10,epsv_x0.1")
    p.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "results"))
    p.add_argument("--tag", default="cpu")
    p.add_argument("--timeout", type=float, default=3600)
    args = p.parse_args(argv)
    args.extra = extra
    if not os.path.exists(os.path.join(SCENES, args.member + ".json")):
        p.error("no member %r in %s" % (args.member, SCENES))
    variants = args.variants.split(",")
    for v in variants:
        try:
            apply_variant({}, v)
        except ValueError as e:
            p.error(str(e))
    if args.elements and args.elements < 8:
        p.error("--elements must be at least 8")
    rows = []
    with tempfile.TemporaryDirectory() as workdir:
        for v in variants:
            rows += run_variant(args, v, workdir)
    print_table(rows, variants)
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "heavy_steps_%s.csv" % args.tag)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    print("wrote", path)
    short = [v for v in variants if sum(1 for r in rows if r["variant"] == v) != int(args.steps)]
    if short:
        print("fewer step lines than --steps %s: %s" % (args.steps, ", ".join(short)), file=sys.stderr)
    return 0 if rows and not short and all(r["status"] == 0 for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
