#!/usr/bin/env python3
"""Reads a settle-box case file (cases/bench/settle_box_*.toml) and prints the numbers the
LIGGGHTS input needs as shell assignments, so both codes run the same setup by construction.

usage: case_params.py CASE.toml [DATAFILE]
  prints name=value lines for `eval`; with DATAFILE also writes the LIGGGHTS data file of the
  initial lattice (read_data).

Refuses (exit 1, naming the key) a case this comparison cannot express: more than one
material, a group that is not a lattice, diameters that differ, a wall that is not one closed
axis-aligned box, no fixed [particles] substep.
"""
import math
import sys
import tomllib


def fail(message):
    print(f"case_params.py: {sys.argv[1]}: {message}", file=sys.stderr)
    sys.exit(1)


def main():
    with open(sys.argv[1], "rb") as f:
        case = tomllib.load(f)
    if "fluid" in case:
        fail("[fluid]: the LIGGGHTS comparison is DEM-only")
    p = case.get("particles") or fail("[particles] is missing")
    materials = p.get("materials", [])
    if len(materials) != 1:
        fail(f"particles.materials: {len(materials)} materials, the comparison takes exactly one")
    m = materials[0]
    groups = p.get("groups", [])
    if not groups or any(g.get("placement") != "lattice" for g in groups):
        fail("particles.groups: the comparison takes groups with placement = \"lattice\" only")
    diameters = {g["diameter"] if isinstance(g["diameter"], (int, float)) else None for g in groups}
    if len(diameters) != 1 or None in diameters:
        fail("particles.groups.*.diameter: the comparison takes one fixed diameter for every group")
    d = diameters.pop()
    if p.get("feed"):
        fail("particles.feed: the comparison has no feed")
    substep = p.get("substep") or fail("particles.substep: the comparison needs a fixed DEM sub-step (the same Δt in both codes)")
    walls = case.get("walls", [])
    if len(walls) != 1 or walls[0]["shape"].get("type") != "box" or walls[0]["shape"].get("open"):
        fail("walls: the comparison takes exactly one closed box wall (the six planes of LIGGGHTS)")
    box = walls[0]["shape"]
    t = case["time"]
    dt, steps = t.get("dt"), t.get("steps")
    if dt is None or steps is None:
        fail("time: the comparison needs a fixed dt and a number of steps")
    # spillage: N_sub = ⌈dt/substep⌉ per outer step (model/src/closure/collision_time.rs)
    n_sub = max(1, math.ceil(dt / substep * (1.0 - 1e-12)))
    sites = [site for g in groups for site in lattice_sites(g)]
    gravity = case.get("physics", {}).get("gravity", [0.0, 0.0, -9.81])
    g_norm = math.sqrt(sum(c * c for c in gravity))
    values = {
        "case_name": case["case"]["name"],
        "diameter": d,
        "density": m["density"],
        "youngs": m["youngs_modulus"] / m.get("softening", 1.0),
        "poisson": m["poisson_ratio"],
        "restitution": m["restitution"],
        "friction": m["friction"],
        "slip_test": p.get("slip_test", "thesis"),
        "substep": substep,
        "substeps_per_step": n_sub,
        "outer_steps": steps,
        "total_substeps": n_sub * steps,
        "n_particles": len(sites),
        "bx0": box["min"][0], "by0": box["min"][1], "bz0": box["min"][2],
        "bx1": box["max"][0], "by1": box["max"][1], "bz1": box["max"][2],
        "g_norm": g_norm,
        "gx": gravity[0] / g_norm if g_norm else 0.0,
        "gy": gravity[1] / g_norm if g_norm else 0.0,
        "gz": gravity[2] / g_norm if g_norm else -1.0,
    }
    if len(sys.argv) > 2:
        write_data(sys.argv[2], values, sites)
    for key, value in values.items():
        print(f"{key}={value!r}")


def lattice_sites(g):
    """The sites of one lattice group exactly as spillage places them (model/src/particles/
    initial.rs): floor((max − min)/spacing + 1e-9) per direction, min + (i + ½)·spacing, in z, y,
    x order; the same formula in binary64 gives the same bits."""
    spacing, lo, hi = g["spacing"], g["region"]["min"], g["region"]["max"]
    n = [int(math.floor((hi[k] - lo[k]) / spacing + 1e-9)) for k in range(3)]
    return [
        (lo[0] + (ix + 0.5) * spacing, lo[1] + (iy + 0.5) * spacing, lo[2] + (iz + 0.5) * spacing)
        for iz in range(n[2])
        for iy in range(n[1])
        for ix in range(n[0])
    ]


def write_data(path, v, sites):
    """The LIGGGHTS data file (atom_style granular: id type diameter density x y z), ids in
    spillage's order."""
    d = v["diameter"]
    with open(path, "w") as f:
        f.write(f"settle box lattice from {sys.argv[1]}\n\n{len(sites)} atoms\n1 atom types\n\n")
        # the simulation domain: the box walls plus one diameter of margin
        for axis, lo, hi in (("x", v["bx0"], v["bx1"]), ("y", v["by0"], v["by1"]), ("z", v["bz0"], v["bz1"])):
            f.write(f"{lo - d!r} {hi + d!r} {axis}lo {axis}hi\n")
        f.write("\nAtoms\n\n")
        for i, (x, y, z) in enumerate(sites):
            f.write(f"{i + 1} 1 {d!r} {v['density']!r} {x!r} {y!r} {z!r}\n")


if __name__ == "__main__":
    main()
